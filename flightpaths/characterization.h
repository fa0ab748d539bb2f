#pragma once
// The ICP characterization positions of thesis Experiment 1 (Figure 14),
// characterization.csv: 558 positions, 10-110 m, zero attitude, spread over
// the image plane. A pure function of the rig and the options.

#include <cstddef>
#include <vector>

#include "aar/flight_path.h"
#include "aar/rig.h"
#include "receiver_box.h"

namespace aar::flightpaths {

/// The ICP characterization positions (thesis Experiment 1, Figure 14).
/// `range_shells` * (grid points) must equal `count`. Defaults: 18 shells of
/// 5.56 m from 10 to 110 m, each with a 7 x 5 image-plane grid without its
/// 4 corners (31 points) = 558 samples. Sample j has range
/// min + (max - min) (j + 0.5) / count (ranges evenly spaced, ascending); the
/// 31 grid points of a shell take the shell's 31 ranges in a fixed scrambled
/// order (point k gets slot (k * range_scramble) mod 31).
struct CharacterizationOptions {
  size_t count = 558;             ///< number of samples (thesis: 558)
  double min_range_m = 10.0;      ///< [m]
  double max_range_m = 110.0;     ///< [m]
  size_t range_shells = 18;       ///< range strata
  int grid_columns = 7;           ///< image-plane grid across the image
  int grid_rows = 5;              ///< image-plane grid down the image
  bool drop_grid_corners = true;  ///< leave out the grid's 4 corner points
  size_t range_scramble = 19;     ///< multiplier for the range slot order; coprime to the grid size
  /// Smallest distance of a box corner to an image border when the box fits [px]
  /// (keeps the fit after the CSV's 0.1 mm rounding).
  double edge_margin_px = 2.0;
  /// When the box cannot fit inside both images at a range (below ~22 m for the
  /// default box), the grid spans this fraction of the half field of view
  /// around the box-centred direction; the reference point stays in view and
  /// the box is partly outside.
  double partial_view_spread = 0.5;

  /// Throws aar::Error naming the field when the options are inconsistent.
  void Check() const;
};

/// The characterization positions, ascending range, time_s = sample index.
std::vector<FlightSample> GenerateCharacterization(const StereoRig& rig, const CharacterizationOptions& options = {},
                                                   const ReceiverBox& box = {});

/// Smallest range at which the box (zero attitude, box-centred direction)
/// fits inside both images with `margin_px`; found by bisection in [1, 1000] m.
double MinimumFitRange(const StereoRig& rig, const ReceiverBox& box, double margin_px = 0.0);

}  // namespace aar::flightpaths
