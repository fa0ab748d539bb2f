#pragma once
// The temporal filter over a sequence of pose estimates (docs/analysis.md, "The temporal filter"): at each frame, a
// constant-velocity fit (position and attitude, each a straight line in time) through the estimates of the last
// `window_s` seconds, evaluated at the frame's own time. It is causal (a frame's filtered pose uses that frame and
// earlier ones only, so it can run live) and it does not lag on constant-velocity motion: the line is read at its
// newest end, not at the window's centre.

#include <optional>
#include <vector>

#include "aar/pose.h"

namespace aar {

struct PoseFilterOptions {
  /// Length of the fit window [s]; frames whose time is at most this much
  /// earlier take part. A straight-line fit over a window W read at its newest
  /// end is off by a W^2 / 12 under an acceleration a, which for a motion of
  /// period T is (2 pi W / T)^2 / 12 of its amplitude: 0.1 s keeps that under
  /// 1 % for periods down to 1.8 s (an aircraft's short-period mode and
  /// gust response are slower), and at 125 Hz fits 13 frames. Below two frame
  /// intervals the filter returns the estimates unchanged.
  double window_s = 0.1;
};

/// One frame of the sequence: its time and its estimate (none when the frame
/// was not measured).
struct TimedPose {
  double time_s = 0.0;
  std::optional<Pose> pose;
};

/// The filtered pose of each frame, in the same order: none where the frame
/// has no estimate. A frame without an estimate, or a time that does not
/// increase, starts the window again; with fewer than three estimates in the
/// window the filtered pose is the frame's own estimate. The attitude's line is
/// fitted to the rotations relative to the newest one (their logarithms), so
/// it has no trouble at the angles' wrap-around.
std::vector<std::optional<Pose>> FilterPoses(const std::vector<TimedPose>& frames, const PoseFilterOptions& options);

}  // namespace aar
