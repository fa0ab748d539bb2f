#pragma once
// Deterministic generators for the committed flight paths (flightpaths/README.md):
//
//   conops.csv            the AAR CONOPS approach of thesis 3.1/3.7 (Figures 20-23):
//                         175 m -> contact position, holds near 49, 34 and 32 m
//   characterization.csv  the 558 ICP characterization positions of Experiment 1
//                         (Figure 14), 10-110 m, zero attitude
//
// Everything here is a pure function of the rig and the options: no clocks, no
// random numbers. Ranges are measured from the left camera centre to the
// receiver reference point (docs/frames.md). Positions are in the tanker frame.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "aar/flight_path.h"
#include "aar/pose.h"
#include "aar/rig.h"

namespace aar::flightpaths {

/// Conservative axis-aligned bounding box of the receiver in the receiver
/// frame (x forward, y left, z up). Approximate C-12 dimensions until the
/// model lands in scenes/c12.glb.
struct ReceiverBox {
  Eigen::Vector3d min_m{-7.9, -8.4, -1.7};  ///< tail, right wing tip, belly [m]
  Eigen::Vector3d max_m{5.5, 8.4, 3.1};     ///< nose, left wing tip, fin top [m]

  /// The 8 corners in the receiver frame.
  std::vector<Eigen::Vector3d> Corners() const;
  Eigen::Vector3d Centre() const { return 0.5 * (min_m + max_m); }
};

/// How the box projects for one pose.
struct BoxVisibility {
  int corners_in_left = 0;                  ///< corners projecting inside the left image (of 8)
  int corners_in_right = 0;                 ///< same for the right image
  double min_margin_px = 0.0;               ///< smallest distance of a corner to an image border, both images; negative when outside
  bool reference_in_both = false;           ///< the reference point projects inside both images
  bool FullyInBoth() const { return corners_in_left == 8 && corners_in_right == 8; }
};

/// Projects the 8 box corners (posed by `tanker_from_receiver`) into both
/// cameras. A corner behind a camera counts as outside with margin -1e9.
BoxVisibility ComputeBoxVisibility(const StereoRig& rig, const ReceiverBox& box, const Pose& tanker_from_receiver);

/// Distance from the left camera centre to the receiver reference point [m].
double RangeFromLeftCamera(const StereoRig& rig, const Pose& tanker_from_receiver);

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
  double time_step_s = 0.5;        ///< uniform sample spacing [s]
  double start_range_m = 174.9;    ///< first sample; just inside region A (<= 175 m) despite the wander [m]
  double start_speed_mps = 2.5;    ///< closure speed at the start [m/s]
  /// The last leg ends this far beyond the contact position's range, on the
  /// same line of sight, so that the wander (about +-8 mm in range) keeps every
  /// sample of the final hold inside region C, whose lower bound (32 m) is the
  /// contact range of scenes/rig.json (32.0009 m) [m].
  double contact_standoff_m = 0.02;
  /// Waypoints after the start; the last leg must end at the contact position
  /// (end_range_m <= 0) at rest.
  std::vector<ApproachLeg> legs = {
      {120.0, 2.0},                // region A: a few m/s, slowing
      {90.0, 1.4},
      {70.0, 1.0},
      {55.0, 0.6},                 // region B
      {49.0, 0.0, 0.2, 40.0},      // hold near 49 m
      {42.0, 0.5},
      {38.0, 0.4},                 // enter region C at 0.4 m/s
      {34.0, 0.0, 0.2, 40.0},      // hold near 34 m
      {0.0, 0.0, 0.2, 60.0},       // to the contact position (~32 m, peak 0.375 m/s) and hold
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
};

/// The ICP characterization positions (thesis Experiment 1, Figure 14).
/// `range_shells` * (grid points) must equal `count`. Defaults: 18 shells of
/// 5.56 m from 10 to 110 m, each with a 7 x 5 image-plane grid without its
/// 4 corners (31 points) = 558 samples. Sample j has range
/// min + (max - min) (j + 0.5) / count (ranges evenly spaced, ascending); the
/// 31 grid points of a shell take the shell's 31 ranges in a fixed scrambled
/// order (point k gets slot (k * range_scramble) mod 31).
struct CharacterizationOptions {
  size_t count = 558;           ///< number of samples (thesis: 558)
  double min_range_m = 10.0;    ///< [m]
  double max_range_m = 110.0;   ///< [m]
  size_t range_shells = 18;     ///< range strata
  int grid_columns = 7;         ///< image-plane grid across the image
  int grid_rows = 5;            ///< image-plane grid down the image
  bool drop_grid_corners = true;  ///< leave out the grid's 4 corner points
  size_t range_scramble = 19;   ///< multiplier for the range slot order; coprime to the grid size
  /// Smallest distance of a box corner to an image border when the box fits [px]
  /// (keeps the fit after the CSV's 0.1 mm rounding).
  double edge_margin_px = 2.0;
  /// When the box cannot fit inside both images at a range (below ~22 m for the
  /// default box), the grid spans this fraction of the half field of view
  /// around the box-centred direction; the reference point stays in view and
  /// the box is partly outside.
  double partial_view_spread = 0.5;
};

/// A hold: a run of consecutive samples in which the receiver is near-stationary.
struct Hold {
  size_t first = 0;            ///< index of the first sample
  size_t count = 0;            ///< number of samples
  double mean_range_m = 0.0;   ///< [m]
  double range_spread_m = 0.0; ///< max - min range over the hold [m]
  double duration_s = 0.0;     ///< time from first to last sample [s]
};

/// Maximal runs of consecutive samples in which every step changes the range
/// by at most `max_speed_mps` * dt, lasting at least `min_duration_s`. The
/// default 2 cm/s lies above the wander's range rate (< 1.3 cm/s) and far
/// below the approach speeds.
std::vector<Hold> FindHolds(const StereoRig& rig, const std::vector<FlightSample>& samples, double max_speed_mps = 0.02,
                            double min_duration_s = 5.0);

/// The CONOPS approach. Throws aar::Error on inconsistent options. Values are
/// rounded to the CSV precision (time 1 ms, metres and degrees 1e-4), so
/// FormatFlightPath/ReadFlightPath round-trips them exactly.
std::vector<FlightSample> GenerateConops(const StereoRig& rig, const ConopsOptions& options = {});

/// The characterization positions, ascending range, time_s = sample index.
std::vector<FlightSample> GenerateCharacterization(const StereoRig& rig, const CharacterizationOptions& options = {},
                                                   const ReceiverBox& box = {});

/// Smallest range at which the box (zero attitude, box-centred direction)
/// fits inside both images with `margin_px`; found by bisection in [1, 1000] m.
double MinimumFitRange(const StereoRig& rig, const ReceiverBox& box, double margin_px = 0.0);

/// Human-readable summary printed by aar-make-flightpaths: per region / range
/// bin sample counts, samples whose box is not fully inside both images, the
/// ranges where that happens, and the holds.
std::string DescribeConops(const StereoRig& rig, const std::vector<FlightSample>& samples, const ReceiverBox& box = {});
std::string DescribeCharacterization(const StereoRig& rig, const std::vector<FlightSample>& samples,
                                     const ReceiverBox& box = {});

}  // namespace aar::flightpaths
