#include "conops.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "aar/error.h"

namespace aar::flightpaths {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

double SmoothStep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

double SumOfSinusoids(const std::vector<Sinusoid>& terms, double t) {
  double sum = 0.0;
  for (const Sinusoid& term : terms) {
    sum += term.amplitude * std::sin(2.0 * std::numbers::pi * t / term.period_s + term.phase_rad);
  }
  return sum;
}

void CheckSinusoids(const std::vector<Sinusoid>& terms, const char* name) {
  for (const Sinusoid& term : terms) {
    if (!std::isfinite(term.amplitude) || !std::isfinite(term.phase_rad) || !(term.period_s > 0.0)) {
      throw Error(std::string("conops options: ") + name +
                  ": sinusoid needs a finite amplitude and phase and a positive period");
    }
  }
}

/// One piece of the range-versus-time profile: a quintic from r0 to r1 with
/// closure speeds v0, v1 and zero acceleration at both ends, or a hold.
struct Segment {
  double t0 = 0.0;
  double duration = 0.0;
  double r0 = 0.0;
  double r1 = 0.0;
  double v0 = 0.0;
  double v1 = 0.0;
  bool hold = false;

  double RangeAt(double t) const {
    if (hold) return r0;
    const double s = std::clamp((t - t0) / duration, 0.0, 1.0);
    const double d = r0 - r1;
    // h(0)=0, h'(0)=a0, h(1)=1, h'(1)=a1, h''(0)=h''(1)=0 (h' in units of d / duration).
    const double a0 = v0 * duration / d;
    const double a1 = v1 * duration / d;
    const double c3 = 10.0 - 6.0 * a0 - 4.0 * a1;
    const double c4 = 8.0 * a0 + 7.0 * a1 - 15.0;
    const double c5 = 6.0 - 3.0 * a0 - 3.0 * a1;
    const double h = s * (a0 + s * s * (c3 + s * (c4 + s * c5)));
    return r0 - d * h;
  }
};

std::vector<Segment> BuildSegments(const ConopsOptions& o, double contact_range_m) {
  const double final_range_m = contact_range_m + o.contact_standoff_m;
  if (!(o.start_range_m > final_range_m)) throw Error("conops options: start_range_m must exceed the contact range");
  std::vector<Segment> segments;
  double t = 0.0;
  double r = o.start_range_m;
  double v = o.start_speed_mps;
  for (size_t i = 0; i < o.legs.size(); ++i) {
    const ApproachLeg& leg = o.legs[i];
    const std::string where = "conops options: leg " + std::to_string(i + 1);
    const bool last = i + 1 == o.legs.size();
    const double end = leg.end_range_m <= 0.0 ? final_range_m : leg.end_range_m;
    if (last != (leg.end_range_m <= 0.0))
      throw Error(where + ": only the last leg (and it) must end at the contact position");
    if (!(end < r)) throw Error(where + ": end range must be below the previous one");
    if (!(end >= final_range_m)) throw Error(where + ": end range is inside the final (contact) range");
    if (!(leg.end_speed_mps >= 0.0) || !(leg.hold_s >= 0.0)) throw Error(where + ": negative speed or hold");
    if (leg.hold_s > 0.0 && leg.end_speed_mps != 0.0) throw Error(where + ": a hold needs end_speed_mps == 0");
    if (last && leg.end_speed_mps != 0.0) throw Error(where + ": the last leg must end at rest");
    Segment seg;
    seg.t0 = t;
    seg.r0 = r;
    seg.r1 = end;
    seg.v0 = v;
    seg.v1 = leg.end_speed_mps;
    if (seg.v0 + seg.v1 > 0.0) {
      seg.duration = 2.0 * (r - end) / (seg.v0 + seg.v1);
    } else {
      if (!(leg.rest_to_rest_mean_speed_mps > 0.0))
        throw Error(where + ": rest_to_rest_mean_speed_mps must be positive");
      seg.duration = (r - end) / leg.rest_to_rest_mean_speed_mps;
    }
    segments.push_back(seg);
    t += seg.duration;
    if (leg.hold_s > 0.0) {
      Segment hold;
      hold.t0 = t;
      hold.duration = leg.hold_s;
      hold.r0 = hold.r1 = end;
      hold.hold = true;
      segments.push_back(hold);
      t += leg.hold_s;
    }
    r = end;
    v = leg.end_speed_mps;
  }
  return segments;
}

double NominalRange(const std::vector<Segment>& segments, double t) {
  for (const Segment& seg : segments) {
    if (t <= seg.t0 + seg.duration) return seg.RangeAt(t);
  }
  return segments.back().r1;
}

}  // namespace

void ConopsOptions::Check() const {
  CheckSinusoids(roll, "roll");
  CheckSinusoids(pitch, "pitch");
  CheckSinusoids(yaw, "yaw");
  CheckSinusoids(wander_x, "wander_x");
  CheckSinusoids(wander_y, "wander_y");
  CheckSinusoids(wander_z, "wander_z");
  if (!(lateral_zero_range_m < start_range_m))
    throw Error("conops options: lateral_zero_range_m must be below start_range_m");
  if (!(level_range_m >= 0.0) || !(level_range_m < start_range_m))
    throw Error("conops options: level_range_m must be >= 0 and below start_range_m");
  if (!(level_blend_m > 0.0)) throw Error("conops options: level_blend_m must be positive");
  if (!(contact_standoff_m >= 0.0)) throw Error("conops options: contact_standoff_m must be >= 0");
  if (!(time_step_s > 0.0)) throw Error("conops options: time_step_s must be positive");
  if (legs.empty()) throw Error("conops options: no legs");
  if (!(start_speed_mps >= 0.0)) throw Error("conops options: start_speed_mps must be >= 0");
}

std::vector<FlightSample> GenerateConops(const StereoRig& rig, const ConopsOptions& o) {
  o.Check();
  const Eigen::Vector3d camera = rig.left.tanker_from_camera.translation();
  const Eigen::Vector3d to_contact = rig.contact_position_m - camera;
  const double contact_range = to_contact.norm();
  // Depression of the contact position below the horizontal, in the vertical
  // plane through the camera (the lateral component is handled separately).
  const double contact_depression_deg = std::atan2(-to_contact.z(), -to_contact.x()) * kRadToDeg;
  if (!(to_contact.x() < 0.0)) throw Error("conops: the contact position must be aft of the left camera");

  const std::vector<Segment> segments = BuildSegments(o, contact_range);
  const double total_s = segments.back().t0 + segments.back().duration;
  const size_t count = static_cast<size_t>(std::floor(total_s / o.time_step_s + 1e-9)) + 1;

  std::vector<FlightSample> samples;
  samples.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) * o.time_step_s;
    const double r = NominalRange(segments, t);
    const double lateral_m =
        o.far_lateral_offset_m * SmoothStep((r - o.lateral_zero_range_m) / (o.start_range_m - o.lateral_zero_range_m));
    const double dy = to_contact.y() + lateral_m;
    const double rho = std::sqrt(std::max(r * r - dy * dy, 0.0));
    double depression_deg = 0.0;
    if (o.level_range_m > 0.0) {
      // Level at the contact height: rho sin(depression) = the contact's drop below the camera.
      const double level_deg = std::asin(std::clamp(-to_contact.z() / rho, -1.0, 1.0)) * kRadToDeg;
      depression_deg =
          level_deg + (o.far_depression_deg - level_deg) * SmoothStep((r - o.level_range_m) / o.level_blend_m);
    } else {
      depression_deg = contact_depression_deg + (o.far_depression_deg - contact_depression_deg) *
                                                    SmoothStep((r - contact_range) / (o.start_range_m - contact_range));
    }
    const double d = depression_deg * kDegToRad;
    FlightSample s;
    s.time_s = t;
    s.tanker_from_receiver.translation_m =
        camera + Eigen::Vector3d(-rho * std::cos(d), dy, -rho * std::sin(d)) +
        Eigen::Vector3d(SumOfSinusoids(o.wander_x, t), SumOfSinusoids(o.wander_y, t), SumOfSinusoids(o.wander_z, t));
    s.tanker_from_receiver.roll_deg = SumOfSinusoids(o.roll, t);
    s.tanker_from_receiver.pitch_deg = SumOfSinusoids(o.pitch, t);
    s.tanker_from_receiver.yaw_deg = SumOfSinusoids(o.yaw, t);
    samples.push_back(RoundToCsvPrecision(s));
  }
  return samples;
}

ConopsOptions LevelConopsOptions() {
  ConopsOptions o;
  o.far_depression_deg = 32.0;
  o.level_range_m = 37.0;
  o.level_blend_m = 8.0;
  return o;
}

}  // namespace aar::flightpaths
