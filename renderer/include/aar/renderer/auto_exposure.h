#pragma once
// Auto-exposure with its lag (docs/rendering.md, "Exposure and night"): the
// camera meters each frame it takes and sets the next frame's exposure
// towards a target level, through a first-order lag. Pure CPU: the metering
// renders come from a callback (the render job renders each frame small,
// stereo_render_job.cpp), so that the controller is tested on its own.

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "aar/image.h"

namespace aar {

struct AutoExposureOptions {
  /// The metered level the camera aims at: the mean luminance of its image
  /// over the image's full scale (0.18: middle grey, the reflectance light
  /// meters are calibrated to).
  double target = 0.18;
  /// The lag: each frame moves the exposure 1 - exp(-dt / time_constant_s)
  /// of the way, in EV, to the one that would have met the target [s].
  double time_constant_s = 0.1;
  /// The most exposure the camera has [EV over the rig's]: its longest
  /// shutter, widest aperture and highest gain; the tool's limit by default.
  double max_ev = 24.0;
  /// The metering image is the pinhole render shrunk by this factor in each direction.
  int meter_downscale = 8;
  void Check() const;
};

/// Every frame's exposure [EV] and the level the camera metered in it.
struct AutoExposureSchedule {
  std::vector<double> ev;
  std::vector<double> metered;
  double full_scale = 1.0;  ///< the radiance the image holds at most, that levels are of
};

/// The metered level of a frame: the mean over the pixels of the luminance
/// (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B) of `radiance` x `factor`,
/// each clipped at `full_scale` (what the camera's image holds at most),
/// over `full_scale`.
double MeteredLevel(const LinearImage& radiance, double factor, double full_scale);

/// The controller over a path of frames at `times_s` (increasing): frame 0
/// at `initial_ev`; frame n metered at its exposure e_n, frame n + 1 at
/// e_n + a (e_n + log2(target / level_n) - e_n), a = 1 - exp(-(t_n+1 - t_n) /
/// time_constant_s), clamped to [-10, max_ev] EV (a black frame: towards max_ev).
/// `render(n)` gives frame n's metering render in the renderer's units
/// (divided by `render_scale` with the exposure's 2^e).
AutoExposureSchedule RunAutoExposure(const std::vector<double>& times_s, double initial_ev, double render_scale,
                                     double full_scale, const AutoExposureOptions& options,
                                     const std::function<LinearImage(size_t)>& render);

/// The manifest's record (frames.auto_exposure, docs/dataset-format.md):
/// the options, the model in words, each frame's ev and metered level.
nlohmann::json AutoExposureJson(const AutoExposureOptions& options, double initial_ev, double render_scale,
                                const AutoExposureSchedule& schedule);

}  // namespace aar
