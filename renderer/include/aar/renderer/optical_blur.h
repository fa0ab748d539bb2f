#pragma once
// Optical blur of a linear image by a Gaussian point-spread function
// (docs/rendering.md, "Sensor model"): the lens and sensor's blur, applied in
// linear light before the sensor's noise.

#include "aar/image.h"

namespace aar {

/// Half-width of the blur kernel [px]: the Gaussian is cut at 3 sigma,
/// ceil(3 sigma_px), and the cut kernel normalised to sum 1.
int GaussianKernelRadius(double sigma_px);

/// The image convolved with a Gaussian of standard deviation `sigma_px`
/// (separable: rows, then columns; each channel alone). Pixels beyond the
/// border repeat the edge pixel, so a uniform image is unchanged and the
/// mean of an image whose border band (the kernel radius wide) is uniform is
/// kept. sigma_px = 0 returns the image as it is. Deterministic: a fixed
/// summation order per pixel.
LinearImage GaussianBlur(const LinearImage& image, double sigma_px);

}  // namespace aar
