#pragma once
// The yardstick of the speed targets (docs/performance.md, "The yardstick"):
// the time OpenCV's StereoBM with the thesis's settings takes on a frame, so
// that stage times measured on different machines, or on one machine under
// different load, compare as ratios.

#include <cstddef>

#include "aar/analyzer/disparity.h"
#include "aar/opened_dataset.h"

namespace aar {

/// Times [ms] OpenCV's StereoBM (48 disparities, block 9, OpenCV's other
/// defaults, its speckle filter at 100 px and 2 px) on the whole rectified
/// pair of frame `index` of `dataset`, on the calling thread (set OpenCV to
/// one thread for one core). Throws aar::Error naming a frame that cannot be
/// read.
double TimeStereoBmYardstick(const OpenedDataset& dataset, const Rectifier& rectifier, size_t index);

/// The reference yardstick the speed targets are written for [ms].
constexpr double kReferenceYardstickMs = 12.7;

}  // namespace aar
