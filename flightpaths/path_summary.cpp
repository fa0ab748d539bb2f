#include "path_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "aar/region.h"
#include "aar/text.h"
#include "characterization.h"
#include "holds.h"

namespace aar::flightpaths {
namespace {

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
    out << " (range " << Fixed(min_range_m, 1) << "-" << Fixed(max_range_m, 1)
        << " m), box not fully inside both images: " << not_fully_in_both;
    if (not_fully_in_both > 0) {
      out << " (at " << Fixed(partial_min_range_m, 1) << "-" << Fixed(partial_max_range_m, 1) << " m)";
    }
    out << ", reference point outside an image: " << reference_outside << ", smallest corner margin "
        << (min_margin_px < -1e8 ? std::string("behind camera") : Fixed(min_margin_px, 1) + " px") << "\n";
    return out.str();
  }
};

}  // namespace

std::string DescribeConops(const StereoRig& rig, const std::vector<FlightSample>& samples, const ReceiverBox& box) {
  std::ostringstream out;
  if (samples.empty()) return "conops: no samples\n";
  const double first_range = RangeFromLeftCamera(rig, samples.front().tanker_from_receiver);
  const double last_range = RangeFromLeftCamera(rig, samples.back().tanker_from_receiver);
  const double dt = samples.size() > 1 ? samples[1].time_s - samples[0].time_s : 0.0;
  out << "conops: " << samples.size() << " samples, time step " << Fixed(dt, 3) << " s, "
      << Fixed(samples.front().time_s, 1) << "-" << Fixed(samples.back().time_s, 1) << " s, range "
      << Fixed(first_range, 2) << " -> " << Fixed(last_range, 2) << " m\n";
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
    out << "  hold near " << Fixed(hold.mean_range_m, 2) << " m: " << hold.count << " samples, "
        << Fixed(hold.duration_s, 1) << " s (t = " << Fixed(samples[hold.first].time_s, 1) << " s), range spread "
        << Fixed(hold.range_spread_m * 1000.0, 1) << " mm\n";
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
