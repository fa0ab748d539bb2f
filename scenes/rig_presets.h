#pragma once
// The committed stereo rigs (scenes/rig.json, scenes/rig-thesis.json,
// scenes/rig-distorted.json, scenes/rig-noisy.json) as presets, and their aar-rig text. Written by aar-make-rig; a pure
// function of the preset, so the files are byte-identical from run to run.

#include <array>
#include <optional>
#include <string>

#include "aar/sensor.h"
#include "aar/thermal.h"

namespace aar::scenes {

/// Brown-Conrady coefficients in OpenCV's order (k1, k2, p1, p2, k3).
using LensCoefficients = std::array<double, 5>;

/// A stereo pair of cameras with identical pinhole intrinsics (each with its
/// own lens distortion, zero by default), side by side along the tanker's y
/// axis, looking aft and pitched down, plus the receiver contact position.
struct RigPreset {
  std::string description;
  int image_width = 1024;
  int image_height = 768;
  double f_px = 900.0;                                  ///< fx = fy [px]
  double cx_px = 511.5;                                 ///< principal point [px]
  double cy_px = 383.5;                                 ///< principal point [px]
  std::array<double, 3> centre_m = {-20.0, 0.0, -2.9};  ///< midpoint of the two camera centres (tanker frame) [m]
  double half_baseline_m = 0.25;                        ///< each camera sits this far from the midpoint along y [m]
  double pitch_down_deg = 30.0;                         ///< optical axis below the aft horizontal [deg]
  /// Contact position: contact_range_m from the midpoint, contact_depression_deg
  /// below the aft horizontal, in the tanker's x-z plane.
  double contact_range_m = 32.0;
  double contact_depression_deg = 30.0;
  double near_m = 0.5;
  LensCoefficients left_distortion{};   ///< all zero: pinhole (written as aar-rig/1, no "distortion")
  LensCoefficients right_distortion{};  ///< all zero: pinhole
  std::optional<SensorParams> sensor;   ///< none: the ideal sensor (no "sensor" block; aar-rig/3 when set)
  std::optional<ThermalCamera> lwir;    ///< a thermal pair instead ("lwir" block; aar-rig/4 when set)
};

/// scenes/rig.json: cameras 30 deg down, contact position on the optical axis at 32 m.
RigPreset DefaultRig();
/// scenes/rig-thesis.json: the same cameras pitched 41 deg down, the same
/// contact position (now 11 deg above the optical axis), so that the receiver's
/// T-tail leaves the top of the frame on a level final approach (issue 9, item 1).
RigPreset ThesisRig();

/// scenes/rig-distorted.json (issue 9, item 3): scenes/rig.json's cameras
/// with a realistic barrel distortion each (docs/scenes.md gives the reasoning).
RigPreset DistortedRig();

/// scenes/rig-noisy.json (issue 9, item 4): scenes/rig.json's cameras with
/// an image sensor: noise, fixed pattern, optical blur and an RGGB mosaic.
RigPreset NoisyRig();
/// scenes/rig-rolling.json: rig-noisy.json's cameras and sensor with a
/// rolling shutter (a 30 ms readout).
RigPreset RollingRig();

/// scenes/rig-1080p.json and scenes/rig-2160p.json: scenes/rig.json's
/// cameras at 1920 x 1080 and 3840 x 2160, the same vertical field of view
/// and baseline (focal length 1265.625 and 2531.25 px).
RigPreset Rig1080p();
RigPreset Rig2160p();

/// scenes/rig-lwir.json: an uncooled LWIR pair (640 x 512, 8-14 um, NETD
/// 50 mK) in scenes/rig.json's place with its vertical field of view.
RigPreset LwirRig();

/// The JSON text of a preset (the committed files' layout): aar-rig/1,
/// aar-rig/2 with a "distortion" object per camera when either has any, or
/// aar-rig/3 with a "sensor" block when the preset has a sensor, aar-rig/4
/// with an "lwir" block when it has a thermal camera.
std::string FormatRig(const RigPreset& rig);

}  // namespace aar::scenes
