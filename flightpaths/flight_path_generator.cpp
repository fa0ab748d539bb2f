#include "flight_path_generator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <numbers>
#include <sstream>

#include "aar/error.h"
#include "aar/region.h"
#include "aar/text.h"

namespace aar::flightpaths {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

double Round(double value, double scale) { return std::round(value * scale) / scale; }

/// The CSV precision (FormatFlightPath: time 3 decimals, the rest 4).
FlightSample RoundToCsvPrecision(FlightSample s) {
  s.time_s = Round(s.time_s, 1e3);
  Pose& p = s.tanker_from_receiver;
  for (int i = 0; i < 3; ++i) p.translation_m(i) = Round(p.translation_m(i), 1e4);
  p.roll_deg = Round(p.roll_deg, 1e4);
  p.pitch_deg = Round(p.pitch_deg, 1e4);
  p.yaw_deg = Round(p.yaw_deg, 1e4);
  return s;
}

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
      throw Error(std::string("conops options: ") + name + ": sinusoid needs a finite amplitude and phase and a positive period");
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
  if (!(o.contact_standoff_m >= 0.0)) throw Error("conops options: contact_standoff_m must be >= 0");
  const double final_range_m = contact_range_m + o.contact_standoff_m;
  if (!(o.time_step_s > 0.0)) throw Error("conops options: time_step_s must be positive");
  if (o.legs.empty()) throw Error("conops options: no legs");
  if (!(o.start_range_m > final_range_m)) throw Error("conops options: start_range_m must exceed the contact range");
  if (!(o.start_speed_mps >= 0.0)) throw Error("conops options: start_speed_mps must be >= 0");
  std::vector<Segment> segments;
  double t = 0.0;
  double r = o.start_range_m;
  double v = o.start_speed_mps;
  for (size_t i = 0; i < o.legs.size(); ++i) {
    const ApproachLeg& leg = o.legs[i];
    const std::string where = "conops options: leg " + std::to_string(i + 1);
    const bool last = i + 1 == o.legs.size();
    const double end = leg.end_range_m <= 0.0 ? final_range_m : leg.end_range_m;
    if (last != (leg.end_range_m <= 0.0)) throw Error(where + ": only the last leg (and it) must end at the contact position");
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
      if (!(leg.rest_to_rest_mean_speed_mps > 0.0)) throw Error(where + ": rest_to_rest_mean_speed_mps must be positive");
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

Eigen::Vector3d LeftCentre(const StereoRig& rig) { return rig.left.tanker_from_camera.translation(); }

/// Pixel margin of one point in one camera: distance to the nearest image
/// border (negative outside); -1e9 behind the camera.
double PixelMargin(const Camera& camera, const Eigen::Vector3d& point_in_tanker, bool* inside) {
  const Eigen::Vector3d in_cam = camera.tanker_from_camera.inverse() * point_in_tanker;
  const std::optional<Eigen::Vector2d> pixel = camera.intrinsics.Project(in_cam);
  if (!pixel) {
    *inside = false;
    return -1e9;
  }
  *inside = camera.intrinsics.Contains(*pixel);
  const Intrinsics& k = camera.intrinsics;
  return std::min({pixel->x() + 0.5, pixel->y() + 0.5, k.width_px - 0.5 - pixel->x(), k.height_px - 0.5 - pixel->y()});
}

std::string Fixed(double value, int decimals) { return FormatFixed(value, decimals); }

/// Per-group visibility tally for the summaries.
struct Tally {
  size_t samples = 0;
  size_t not_fully_in_both = 0;
  size_t reference_outside = 0;
  double min_margin_px = std::numeric_limits<double>::infinity();
  double partial_min_range_m = std::numeric_limits<double>::infinity();
  double partial_max_range_m = -std::numeric_limits<double>::infinity();
  double min_range_m = std::numeric_limits<double>::infinity();
  double max_range_m = -std::numeric_limits<double>::infinity();

  void Add(double range_m, const BoxVisibility& vis) {
    ++samples;
    min_range_m = std::min(min_range_m, range_m);
    max_range_m = std::max(max_range_m, range_m);
    min_margin_px = std::min(min_margin_px, vis.min_margin_px);
    if (!vis.reference_in_both) ++reference_outside;
    if (!vis.FullyInBoth()) {
      ++not_fully_in_both;
      partial_min_range_m = std::min(partial_min_range_m, range_m);
      partial_max_range_m = std::max(partial_max_range_m, range_m);
    }
  }

  std::string Line(const std::string& name) const {
    std::ostringstream out;
    out << "  " << name << ": " << samples << " samples";
    if (samples == 0) return out.str() + "\n";
    out << " (range " << Fixed(min_range_m, 1) << "-" << Fixed(max_range_m, 1) << " m), box not fully inside both images: "
        << not_fully_in_both;
    if (not_fully_in_both > 0) {
      out << " (at " << Fixed(partial_min_range_m, 1) << "-" << Fixed(partial_max_range_m, 1) << " m)";
    }
    out << ", reference point outside an image: " << reference_outside << ", smallest corner margin "
        << (min_margin_px < -1e8 ? std::string("behind camera") : Fixed(min_margin_px, 1) + " px") << "\n";
    return out.str();
  }
};

/// Where the characterization grid is centred at range r: the reference
/// point such that the box centre (zero attitude) lies on the line through
/// the midpoint of the two camera centres along the left optical axis.
/// Returned in the left camera frame.
Eigen::Vector3d BoxCentredPoint(const StereoRig& rig, const ReceiverBox& box, double range_m) {
  const Eigen::Isometry3d left_from_tanker = rig.left.tanker_from_camera.inverse();
  const Eigen::Vector3d midpoint = left_from_tanker * (0.5 * (rig.left.tanker_from_camera.translation() +
                                                              rig.right.tanker_from_camera.translation()));
  const Eigen::Vector3d centre_offset = left_from_tanker.linear() * box.Centre();
  const Eigen::Vector3d w = midpoint - centre_offset;
  const double disc = w.z() * w.z() - w.squaredNorm() + range_m * range_m;
  const double t = -w.z() + std::sqrt(std::max(disc, 0.0));
  return w + t * Eigen::Vector3d::UnitZ();
}

Pose PoseFromLeftPoint(const StereoRig& rig, const Eigen::Vector3d& point_in_left) {
  Pose pose;
  pose.translation_m = rig.left.tanker_from_camera * point_in_left;
  return pose;
}

bool BoxFits(const StereoRig& rig, const ReceiverBox& box, const Pose& pose, double margin_px) {
  const BoxVisibility vis = ComputeBoxVisibility(rig, box, pose);
  return vis.FullyInBoth() && vis.min_margin_px >= margin_px;
}

}  // namespace

std::vector<Eigen::Vector3d> ReceiverBox::Corners() const {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? max_m.x() : min_m.x(), (i & 2) ? max_m.y() : min_m.y(),
                         (i & 4) ? max_m.z() : min_m.z());
  }
  return corners;
}

BoxVisibility ComputeBoxVisibility(const StereoRig& rig, const ReceiverBox& box, const Pose& tanker_from_receiver) {
  const Eigen::Isometry3d pose = IsometryFromPose(tanker_from_receiver);
  BoxVisibility vis;
  vis.min_margin_px = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& corner : box.Corners()) {
    const Eigen::Vector3d p = pose * corner;
    bool in_left = false;
    bool in_right = false;
    vis.min_margin_px = std::min(vis.min_margin_px, PixelMargin(rig.left, p, &in_left));
    vis.min_margin_px = std::min(vis.min_margin_px, PixelMargin(rig.right, p, &in_right));
    vis.corners_in_left += in_left ? 1 : 0;
    vis.corners_in_right += in_right ? 1 : 0;
  }
  bool ref_left = false;
  bool ref_right = false;
  PixelMargin(rig.left, tanker_from_receiver.translation_m, &ref_left);
  PixelMargin(rig.right, tanker_from_receiver.translation_m, &ref_right);
  vis.reference_in_both = ref_left && ref_right;
  return vis;
}

double RangeFromLeftCamera(const StereoRig& rig, const Pose& tanker_from_receiver) {
  return (tanker_from_receiver.translation_m - LeftCentre(rig)).norm();
}

std::vector<Hold> FindHolds(const StereoRig& rig, const std::vector<FlightSample>& samples, double max_speed_mps,
                            double min_duration_s) {
  std::vector<double> range(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) range[i] = RangeFromLeftCamera(rig, samples[i].tanker_from_receiver);
  auto still = [&](size_t i) {  // step i-1 -> i
    const double dt = samples[i].time_s - samples[i - 1].time_s;
    return std::abs(range[i] - range[i - 1]) <= max_speed_mps * dt;
  };
  std::vector<Hold> holds;
  size_t i = 0;
  while (i < samples.size()) {
    size_t j = i;
    while (j + 1 < samples.size() && still(j + 1)) ++j;
    const double duration = samples[j].time_s - samples[i].time_s;
    if (duration >= min_duration_s) {
      Hold hold;
      hold.first = i;
      hold.count = j - i + 1;
      double sum = 0.0;
      double lo = range[i];
      double hi = range[i];
      for (size_t k = i; k <= j; ++k) {
        sum += range[k];
        lo = std::min(lo, range[k]);
        hi = std::max(hi, range[k]);
      }
      hold.mean_range_m = sum / static_cast<double>(hold.count);
      hold.range_spread_m = hi - lo;
      hold.duration_s = duration;
      holds.push_back(hold);
    }
    i = j + 1;
  }
  return holds;
}

std::vector<FlightSample> GenerateConops(const StereoRig& rig, const ConopsOptions& o) {
  CheckSinusoids(o.roll, "roll");
  CheckSinusoids(o.pitch, "pitch");
  CheckSinusoids(o.yaw, "yaw");
  CheckSinusoids(o.wander_x, "wander_x");
  CheckSinusoids(o.wander_y, "wander_y");
  CheckSinusoids(o.wander_z, "wander_z");
  const Eigen::Vector3d camera = LeftCentre(rig);
  const Eigen::Vector3d to_contact = rig.contact_position_m - camera;
  const double contact_range = to_contact.norm();
  // Depression of the contact position below the horizontal, in the vertical
  // plane through the camera (the lateral component is handled separately).
  const double contact_depression_deg = std::atan2(-to_contact.z(), -to_contact.x()) * kRadToDeg;
  if (!(to_contact.x() < 0.0)) throw Error("conops: the contact position must be aft of the left camera");
  if (!(o.lateral_zero_range_m < o.start_range_m)) throw Error("conops options: lateral_zero_range_m must be below start_range_m");

  const std::vector<Segment> segments = BuildSegments(o, contact_range);
  const double total_s = segments.back().t0 + segments.back().duration;
  const size_t count = static_cast<size_t>(std::floor(total_s / o.time_step_s + 1e-9)) + 1;

  std::vector<FlightSample> samples;
  samples.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) * o.time_step_s;
    const double r = NominalRange(segments, t);
    const double depression_deg =
        contact_depression_deg +
        (o.far_depression_deg - contact_depression_deg) * SmoothStep((r - contact_range) / (o.start_range_m - contact_range));
    const double lateral_m =
        o.far_lateral_offset_m * SmoothStep((r - o.lateral_zero_range_m) / (o.start_range_m - o.lateral_zero_range_m));
    const double dy = to_contact.y() + lateral_m;
    const double rho = std::sqrt(std::max(r * r - dy * dy, 0.0));
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

double MinimumFitRange(const StereoRig& rig, const ReceiverBox& box, double margin_px) {
  auto fits = [&](double r) { return BoxFits(rig, box, PoseFromLeftPoint(rig, BoxCentredPoint(rig, box, r)), margin_px); };
  double lo = 1.0;
  double hi = 1000.0;
  if (!fits(hi)) return std::numeric_limits<double>::infinity();
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fits(mid) ? hi : lo) = mid;
  }
  return hi;
}

std::vector<FlightSample> GenerateCharacterization(const StereoRig& rig, const CharacterizationOptions& o,
                                                   const ReceiverBox& box) {
  if (o.grid_columns < 1 || o.grid_rows < 1) throw Error("characterization options: grid must be at least 1 x 1");
  if (!(o.min_range_m > 0.0) || !(o.max_range_m > o.min_range_m)) {
    throw Error("characterization options: need 0 < min_range_m < max_range_m");
  }
  if (!(o.partial_view_spread >= 0.0 && o.partial_view_spread <= 1.0)) {
    throw Error("characterization options: partial_view_spread must be in [0, 1]");
  }
  // Grid fractions in [-1, 1] x [-1, 1] (image x right, y down), row-major.
  std::vector<Eigen::Vector2d> grid;
  auto fraction = [](int i, int n) { return n == 1 ? 0.0 : -1.0 + 2.0 * i / (n - 1); };
  for (int row = 0; row < o.grid_rows; ++row) {
    for (int col = 0; col < o.grid_columns; ++col) {
      const bool corner = (row == 0 || row == o.grid_rows - 1) && (col == 0 || col == o.grid_columns - 1);
      if (corner && o.drop_grid_corners && o.grid_rows > 1 && o.grid_columns > 1) continue;
      grid.emplace_back(fraction(col, o.grid_columns), fraction(row, o.grid_rows));
    }
  }
  const size_t per_shell = grid.size();
  if (o.range_shells == 0 || o.range_shells * per_shell != o.count) {
    throw Error("characterization options: range_shells (" + std::to_string(o.range_shells) + ") x grid points (" +
                std::to_string(per_shell) + ") must equal count (" + std::to_string(o.count) + ")");
  }
  if (std::gcd(o.range_scramble, per_shell) != 1) {
    throw Error("characterization options: range_scramble must be coprime to the number of grid points");
  }

  const Intrinsics& k = rig.left.intrinsics;
  const double half_x = 0.5 * k.width_px / k.fx_px;   // half field of view, normalized image units
  const double half_y = 0.5 * k.height_px / k.fy_px;

  std::vector<FlightSample> samples(o.count);
  for (size_t shell = 0; shell < o.range_shells; ++shell) {
    for (size_t g = 0; g < per_shell; ++g) {
      const size_t index = shell * per_shell + (g * o.range_scramble) % per_shell;
      const double r = o.min_range_m + (o.max_range_m - o.min_range_m) * (static_cast<double>(index) + 0.5) /
                                           static_cast<double>(o.count);
      const Eigen::Vector3d centred = BoxCentredPoint(rig, box, r);
      const Eigen::Vector2d origin(centred.x() / centred.z(), centred.y() / centred.z());
      const Eigen::Vector2d cell = grid[g];
      const double ring = std::max(std::abs(cell.x()), std::abs(cell.y()));  // 0 centre .. 1 grid border
      Eigen::Vector2d edge = Eigen::Vector2d::Zero();                       // grid border point on this ray
      if (ring > 0.0) edge = Eigen::Vector2d(cell.x() / ring * half_x, cell.y() / ring * half_y);
      auto point_at = [&](double lambda) {
        const Eigen::Vector2d ab = origin + lambda * edge;
        return Eigen::Vector3d(r * Eigen::Vector3d(ab.x(), ab.y(), 1.0).normalized());
      };
      auto fits = [&](double lambda) { return BoxFits(rig, box, PoseFromLeftPoint(rig, point_at(lambda)), o.edge_margin_px); };
      // Largest lambda along the ray for which the box still fits; the grid
      // point goes to `ring` of it, so the points stay evenly spaced.
      double lambda_edge = o.partial_view_spread;
      if (fits(0.0)) {
        double lo = 0.0;
        double hi = 1.0;
        if (fits(hi)) {
          lo = hi;
        } else {
          for (int i = 0; i < 50; ++i) {
            const double mid = 0.5 * (lo + hi);
            (fits(mid) ? lo : hi) = mid;
          }
        }
        lambda_edge = lo;
      }
      FlightSample s;
      s.time_s = static_cast<double>(index);
      s.tanker_from_receiver = PoseFromLeftPoint(rig, point_at(ring * lambda_edge));
      samples[index] = RoundToCsvPrecision(s);
    }
  }
  return samples;
}

std::string DescribeConops(const StereoRig& rig, const std::vector<FlightSample>& samples, const ReceiverBox& box) {
  std::ostringstream out;
  if (samples.empty()) return "conops: no samples\n";
  const double first_range = RangeFromLeftCamera(rig, samples.front().tanker_from_receiver);
  const double last_range = RangeFromLeftCamera(rig, samples.back().tanker_from_receiver);
  const double dt = samples.size() > 1 ? samples[1].time_s - samples[0].time_s : 0.0;
  out << "conops: " << samples.size() << " samples, time step " << Fixed(dt, 3) << " s, " << Fixed(samples.front().time_s, 1)
      << "-" << Fixed(samples.back().time_s, 1) << " s, range " << Fixed(first_range, 2) << " -> " << Fixed(last_range, 2)
      << " m\n";
  std::map<std::string, Tally> tallies;
  std::map<std::string, double> max_speed;
  double max_attitude = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const Pose& pose = samples[i].tanker_from_receiver;
    const double r = RangeFromLeftCamera(rig, pose);
    const std::string region = RegionForRange(r);
    tallies[region].Add(r, ComputeBoxVisibility(rig, box, pose));
    if (i > 0) {
      const double prev = RangeFromLeftCamera(rig, samples[i - 1].tanker_from_receiver);
      const double speed = (prev - r) / (samples[i].time_s - samples[i - 1].time_s);
      max_speed[region] = std::max(max_speed[region], speed);
    }
    max_attitude = std::max({max_attitude, std::abs(pose.roll_deg), std::abs(pose.pitch_deg), std::abs(pose.yaw_deg)});
  }
  for (const char* region : {"A", "B", "C", "none"}) {
    if (!tallies.contains(region)) continue;
    std::string line = tallies[region].Line(std::string("region ") + region);
    line.pop_back();
    out << line << ", max closure speed " << Fixed(max_speed[region], 2) << " m/s\n";
  }
  out << "  largest |roll|, |pitch|, |yaw|: " << Fixed(max_attitude, 2) << " deg\n";
  for (const Hold& hold : FindHolds(rig, samples)) {
    out << "  hold near " << Fixed(hold.mean_range_m, 2) << " m: " << hold.count << " samples, " << Fixed(hold.duration_s, 1)
        << " s (t = " << Fixed(samples[hold.first].time_s, 1) << " s), range spread " << Fixed(hold.range_spread_m * 1000.0, 1)
        << " mm\n";
  }
  return out.str();
}

std::string DescribeCharacterization(const StereoRig& rig, const std::vector<FlightSample>& samples,
                                     const ReceiverBox& box) {
  std::ostringstream out;
  out << "characterization: " << samples.size() << " samples, zero attitude; the box fits inside both images"
      << " (box-centred direction) from " << Fixed(MinimumFitRange(rig, box), 2) << " m\n";
  std::map<std::string, Tally> tallies;
  for (const FlightSample& s : samples) {
    const double r = RangeFromLeftCamera(rig, s.tanker_from_receiver);
    tallies[RangeBinForRange(r)].Add(r, ComputeBoxVisibility(rig, box, s.tanker_from_receiver));
  }
  for (const char* bin : {"none", "20-60", "60-110"}) {
    if (!tallies.contains(bin)) continue;
    out << tallies[bin].Line(std::string(bin) == "none" ? "below 20 m" : std::string("bin ") + bin + " m");
  }
  return out.str();
}

}  // namespace aar::flightpaths
