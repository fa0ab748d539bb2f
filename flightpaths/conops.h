#pragma once
// The CONOPS approach of thesis 3.1/3.7 (Figures 20-23), conops.csv: 175 m ->
// contact position, holds near 49, 34 and 32 m. A pure function of the rig
// and the options: no clocks, no random numbers.

#include <vector>

#include "aar/flight_path.h"
#include "aar/rig.h"

namespace aar::flightpaths {

/// One sinusoidal component: amplitude * sin(2 pi t / period + phase).
struct Sinusoid {
  double amplitude = 0.0;  ///< [deg] or [m], depending on use
  double period_s = 1.0;   ///< [s]
  double phase_rad = 0.0;  ///< [rad]
};

/// One leg of the approach. The range closes from the previous leg's end (or
/// the start) to `end_range_m`; the closure speed changes smoothly (quintic
/// range profile, zero acceleration at both ends) from the previous end speed
/// to `end_speed_mps`. Leg duration is 2 D / (v_start + v_end), i.e. the mean
/// closure speed is the mean of the end speeds; when both are zero (rest to
/// rest) it is D / `rest_to_rest_mean_speed_mps`. A leg ending at rest may be
/// followed by a hold of `hold_s` seconds at `end_range_m`.
struct ApproachLeg {
  double end_range_m = 0.0;                  ///< [m]; <= 0 means the rig's contact position range
  double end_speed_mps = 0.0;                ///< closure speed at the end of the leg [m/s]
  double rest_to_rest_mean_speed_mps = 0.2;  ///< used only when both end speeds are 0 [m/s]
  double hold_s = 0.0;                       ///< hold after the leg (requires end_speed_mps == 0) [s]
};

/// The CONOPS approach (thesis 3.1, 3.7, Figures 20-23). Defaults give 609
/// samples: region A 118, B 231, C 260, with holds at 49 m (40 s), 34 m (40 s)
/// and the contact position, 32.0 m (60 s).
struct ConopsOptions {
  double time_step_s = 0.5;      ///< uniform sample spacing [s]
  double start_range_m = 174.9;  ///< first sample; just inside region A (<= 175 m) despite the wander [m]
  double start_speed_mps = 2.5;  ///< closure speed at the start [m/s]
  /// The last leg ends this far beyond the contact position's range, on the
  /// same line of sight, so that the wander (about +-8 mm in range) keeps every
  /// sample of the final hold inside region C, whose lower bound (32 m) is the
  /// contact range of scenes/rig.json (32.0009 m) [m].
  double contact_standoff_m = 0.02;
  /// Waypoints after the start; the last leg must end at the contact position
  /// (end_range_m <= 0) at rest.
  std::vector<ApproachLeg> legs = {
      {120.0, 2.0},  // region A: a few m/s, slowing
      {90.0, 1.4},
      {70.0, 1.0},
      {55.0, 0.6},             // region B
      {49.0, 0.0, 0.2, 40.0},  // hold near 49 m
      {42.0, 0.5},
      {38.0, 0.4},             // enter region C at 0.4 m/s
      {34.0, 0.0, 0.2, 40.0},  // hold near 34 m
      {0.0, 0.0, 0.2, 60.0},   // to the contact position (~32 m, peak 0.375 m/s) and hold
  };
  /// Depression of the receiver reference point below the horizontal through
  /// the left camera, in the vertical plane, at start_range_m [deg]. At the
  /// contact range it is the contact position's own (30 deg for scenes/rig.json);
  /// in between it follows a smoothstep in range. With the cameras pitched
  /// 30 deg down and a vertical half field of view of ~23 deg, 15 deg keeps the
  /// far receiver 15 deg above the image centre, inside the view.
  double far_depression_deg = 15.0;
  /// Lateral (tanker y) offset of the receiver from the contact position's y
  /// at start_range_m [m]; smoothstep in range down to 0 at lateral_zero_range_m.
  double far_lateral_offset_m = -3.0;
  double lateral_zero_range_m = 45.0;  ///< range below which the lateral offset is 0 [m]
  /// Level final approach (conops-level.csv, issue 9): when positive, the
  /// receiver flies level at the contact position's height from this range in
  /// (depression asin(height / horizontal distance)); from level_range_m +
  /// level_blend_m out it keeps far_depression_deg, and in between the
  /// depression blends (smoothstep in range) from one to the other, so the
  /// vertical speed is continuous. 0 (the default, conops.csv): the depression
  /// blends to the contact position's own, as described at far_depression_deg [m].
  double level_range_m = 0.0;
  double level_blend_m = 15.0;  ///< range over which the level approach is joined [m]
  /// Attitude: each angle is a sum of sinusoids in time [deg]. The default
  /// amplitudes sum to at most 2.8 deg.
  std::vector<Sinusoid> roll = {{2.0, 47.0, 0.4}, {0.8, 13.0, 1.9}};
  std::vector<Sinusoid> pitch = {{1.2, 61.0, 2.2}, {0.6, 17.0, 0.7}};
  std::vector<Sinusoid> yaw = {{1.8, 73.0, 4.1}, {0.7, 23.0, 3.0}};
  /// Position wander along tanker x, y, z [m] (present throughout the path, so
  /// holds are near-stationary rather than frozen): at most 6 mm per axis.
  std::vector<Sinusoid> wander_x = {{0.0040, 7.3, 0.3}, {0.0020, 2.9, 2.1}};
  std::vector<Sinusoid> wander_y = {{0.0040, 9.1, 1.2}, {0.0020, 3.7, 4.4}};
  std::vector<Sinusoid> wander_z = {{0.0040, 6.1, 5.0}, {0.0020, 3.1, 0.9}};

  /// Throws aar::Error naming the field when an option is out of range on its
  /// own (the legs against each other and the rig are checked by GenerateConops).
  void Check() const;
};

/// The CONOPS approach. Throws aar::Error on inconsistent options. Values are
/// rounded to the CSV precision (time 1 ms, metres and degrees 1e-4), so
/// FormatFlightPath/ReadFlightPath round-trips them exactly.
std::vector<FlightSample> GenerateConops(const StereoRig& rig, const ConopsOptions& options = {});

/// The options of conops-level.csv (for scenes/rig-thesis.json, cameras 41 deg
/// down): the CONOPS approach 32 deg below the camera's horizontal (9 deg above
/// the optical axis) down to 45 m, joining a level path at the contact height
/// at 37 m: the T-tail's top leaves the top of the frame at about 39 m and is
/// back in view at about 36.4 m (flightpaths/README.md).
ConopsOptions LevelConopsOptions();

}  // namespace aar::flightpaths
