#include "aar/renderer/auto_exposure.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "aar/error.h"

namespace aar {
namespace {

// The exposure's range: that of --exposure-ev.
constexpr double kMinEv = -10.0, kMaxEv = 24.0;

}  // namespace

void AutoExposureOptions::Check() const {
  if (!(target > 0.0 && target < 1.0)) {
    throw Error("--ae-target " + std::to_string(target) + ": expected a level between 0 and 1 (of full scale)");
  }
  if (!(time_constant_s >= 0.0 && time_constant_s <= 60.0)) {
    throw Error("--ae-time-constant " + std::to_string(time_constant_s) + ": expected 0 (no lag) to 60 [s]");
  }
  if (!(max_ev >= kMinEv && max_ev <= kMaxEv)) {
    throw Error("--ae-max-ev " + std::to_string(max_ev) + ": expected -10 to 24 [EV]");
  }
  if (meter_downscale < 1 || meter_downscale > 64) {
    throw Error("auto-exposure: a metering downscale of " + std::to_string(meter_downscale) + ", expected 1 to 64");
  }
}

double MeteredLevel(const LinearImage& radiance, double factor, double full_scale) {
  const size_t pixels = radiance.rgb.size() / 3;
  if (pixels == 0) throw Error("auto-exposure: an empty metering image");
  double sum = 0.0;
  for (size_t p = 0; p < pixels; ++p) {
    const float* c = &radiance.rgb[3 * p];
    const double luminance = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    sum += std::clamp(luminance * factor, 0.0, full_scale);
  }
  return sum / static_cast<double>(pixels) / full_scale;
}

AutoExposureSchedule RunAutoExposure(const std::vector<double>& times_s, double initial_ev, double render_scale,
                                     double full_scale, const AutoExposureOptions& options,
                                     const std::function<LinearImage(size_t)>& render) {
  options.Check();
  if (!(full_scale > 0.0) || !(render_scale > 0.0)) throw Error("auto-exposure: full scale and render scale > 0");
  AutoExposureSchedule schedule;
  schedule.full_scale = full_scale;
  double ev = std::clamp(initial_ev, kMinEv, options.max_ev);
  for (size_t n = 0; n < times_s.size(); ++n) {
    const double level = MeteredLevel(render(n), std::exp2(ev) / render_scale, full_scale);
    schedule.ev.push_back(ev);
    schedule.metered.push_back(level);
    if (n + 1 == times_s.size()) break;
    const double wanted = level > 0.0 ? ev + std::log2(options.target / level) : options.max_ev;
    const double dt = times_s[n + 1] - times_s[n];
    if (!(dt > 0.0)) throw Error("auto-exposure: the path's times must increase (row " + std::to_string(n + 2) + ")");
    const double step = options.time_constant_s > 0.0 ? 1.0 - std::exp(-dt / options.time_constant_s) : 1.0;
    ev = std::clamp(ev + step * (wanted - ev), kMinEv, options.max_ev);
  }
  return schedule;
}

nlohmann::json AutoExposureJson(const AutoExposureOptions& options, double initial_ev, double render_scale,
                                const AutoExposureSchedule& schedule) {
  return {{"target", options.target},
          {"time_constant_s", options.time_constant_s},
          {"max_ev", options.max_ev},
          {"initial_ev", initial_ev},
          {"render_scale", render_scale},
          {"full_scale", schedule.full_scale},
          {"meter",
           {{"camera", "left"},
            {"downscale", options.meter_downscale},
            {"samples_per_pixel", 1},
            {"instant", "the frame's"}}},
          {"model",
           "frame 0 at initial_ev; frame n metered at e_n: level_n = mean over the pixels of min(Y x 2^e_n / "
           "render_scale, full_scale) / full_scale, Y the Rec. 709 luminance; e_n+1 = e_n + (1 - exp(-dt / "
           "time_constant_s)) log2(target / level_n), clamped to [-10, max_ev]; both cameras at e_n "
           "(auto_exposure.h)"},
          {"ev", schedule.ev},
          {"metered", schedule.metered}};
}

}  // namespace aar
