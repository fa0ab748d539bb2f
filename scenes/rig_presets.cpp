#include "rig_presets.h"

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace aar::scenes {
namespace {

/// Shortest text that reads back as the same double, with ".0" on integers.
std::string Num(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  if (ec != std::errc()) throw std::runtime_error("rig: cannot format a number");
  std::string s(buffer, end);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

/// cos and sin of an angle in degrees, correctly rounded for the angles used
/// here: evaluated in long double, so that 30 deg gives exactly 0.5 and the
/// double nearest sqrt(3)/2 (std::cos(pi / 6) in double is one ulp off).
void CosSinDeg(double deg, double* c, double* s) {
  const long double rad = static_cast<long double>(deg) * std::numbers::pi_v<long double> / 180.0L;
  *c = static_cast<double>(std::cos(rad));
  *s = static_cast<double>(std::sin(rad));
}

bool Distorted(const RigPreset& r) {
  return r.left_distortion != LensCoefficients{} || r.right_distortion != LensCoefficients{};
}

std::string Camera(const RigPreset& r, double y_m, const LensCoefficients& d) {
  double c = 0.0, s = 0.0;
  CosSinDeg(r.pitch_down_deg, &c, &s);
  // Columns: camera x (image right) = tanker +y; camera z (optical axis) =
  // (-cos, 0, -sin); camera y (image down) = z cross x = (sin, 0, -cos).
  std::ostringstream o;
  o << "      \"fx_px\": " << Num(r.f_px) << ", \"fy_px\": " << Num(r.f_px) << ", \"cx_px\": " << Num(r.cx_px)
    << ", \"cy_px\": " << Num(r.cy_px) << ",\n";
  if (Distorted(r)) {
    o << "      \"distortion\": {\"k1\": " << Num(d[0]) << ", \"k2\": " << Num(d[1]) << ", \"p1\": " << Num(d[2])
      << ", \"p2\": " << Num(d[3]) << ", \"k3\": " << Num(d[4]) << "},\n";
  }
  o << "      \"tanker_from_camera\": {\n"
    << "        \"translation_m\": [" << Num(r.centre_m[0]) << ", " << Num(r.centre_m[1] + y_m) << ", "
    << Num(r.centre_m[2]) << "],\n"
    << "        \"rotation\": [[0.0, " << Num(s) << ", " << Num(-c) << "],\n"
    << "                     [1.0, 0.0, 0.0],\n"
    << "                     [0.0, " << Num(-c) << ", " << Num(-s) << "]]\n"
    << "      }\n";
  return o.str();
}

std::string Sensor(const SensorParams& sensor) {
  std::ostringstream o;
  o << "  \"sensor\": {\"seed\": " << sensor.seed << ", \"exposure_e\": " << Num(sensor.exposure_e)
    << ", \"full_well_e\": " << Num(sensor.full_well_e) << ", \"read_noise_e\": " << Num(sensor.read_noise_e)
    << ",\n             \"prnu\": " << Num(sensor.prnu) << ", \"dsnu_e\": " << Num(sensor.dsnu_e)
    << ", \"adc_bits\": " << sensor.adc_bits << ", \"black_level_dn\": " << sensor.black_level_dn
    << ",\n             \"blur_sigma_px\": " << Num(sensor.blur_sigma_px) << ", \"bayer\": \""
    << (sensor.bayer == BayerPattern::kRggb ? "rggb" : "none") << "\"";
  if (sensor.readout_ms > 0.0) o << ", \"readout_ms\": " << Num(sensor.readout_ms);
  o << "},\n";
  return o.str();
}

std::string Lwir(const ThermalCamera& lwir) {
  std::ostringstream o;
  o << "  \"lwir\": {\"seed\": " << lwir.seed << ", \"band_um\": [" << Num(lwir.band_min_um) << ", "
    << Num(lwir.band_max_um) << "], \"netd_mk\": " << Num(lwir.netd_mk)
    << ", \"nonuniformity_mk\": " << Num(lwir.nonuniformity_mk) << "},\n";
  return o.str();
}

}  // namespace

RigPreset DefaultRig() {
  RigPreset r;
  r.description =
      "Stereo pair under the KC-46-class tanker's aft fuselage, looking aft and 30 deg down. Pinhole cameras, no "
      "distortion. Positions in the tanker body frame (x forward, y left, z up, metres). Rotations are "
      "tanker_from_camera: columns are the camera's x (right), y (down), z (optical axis) expressed in the tanker "
      "frame.";
  return r;
}

RigPreset ThesisRig() {
  RigPreset r = DefaultRig();
  r.pitch_down_deg = 41.0;
  r.description =
      "Thesis geometry (issue 9): the cameras of scenes/rig.json pitched 41 deg down instead of 30, the same contact "
      "position (11 deg above the optical axis), so that on a level final approach the receiver's T-tail leaves the "
      "top of the frame. Pinhole cameras, no distortion. Positions in the tanker body frame (x forward, y left, z up, "
      "metres). Rotations are tanker_from_camera: columns are the camera's x (right), y (down), z (optical axis) "
      "expressed in the tanker frame.";
  return r;
}

RigPreset DistortedRig() {
  RigPreset r = DefaultRig();
  // Barrel distortion of a 900 px / 1024 x 768 (59 deg horizontal) machine-vision
  // lens: -6.3 % radial at the image corner (40 px), -4.4 % at the side edges;
  // decentring terms of 1e-4 as calibrated lenses show. The two lenses differ
  // a little, as two of one model do. Reasoning and sources: docs/scenes.md.
  r.left_distortion = {-0.15, 0.05, 1e-4, -1e-4, 0.0};
  r.right_distortion = {-0.14, 0.045, -1.2e-4, 0.8e-4, 0.0};
  r.description =
      "The cameras of scenes/rig.json with lens distortion (issue 9, item 3): Brown-Conrady coefficients k1 k2 p1 p2 "
      "k3 (OpenCV's model) of a realistic barrel-distorting machine-vision lens, slightly different for the two "
      "cameras. Positions in the tanker body frame (x forward, y left, z up, metres). Rotations are "
      "tanker_from_camera: columns are the camera's x (right), y (down), z (optical axis) expressed in the tanker "
      "frame.";
  return r;
}

namespace {

// scenes/rig.json's cameras at a higher resolution: the same vertical field
// of view (46.2 deg: the height the receiver's approach needs) on a 16:9
// sensor, so the view is wider (74.3 deg); the same baseline.
RigPreset WideRig(int width, int height, const std::string& name) {
  RigPreset r = DefaultRig();
  const RigPreset base;
  r.image_width = width;
  r.image_height = height;
  r.f_px = base.f_px * height / base.image_height;  // 1265.625 px at 1080 rows, 2531.25 at 2160
  r.cx_px = 0.5 * (width - 1);
  r.cy_px = 0.5 * (height - 1);
  r.description = "The cameras of scenes/rig.json at " + name + " (" + std::to_string(width) + " x " +
                  std::to_string(height) +
                  "): the same position, baseline and vertical field of view, a 16:9 sensor and so a wider view. "
                  "Pinhole cameras, no distortion. Positions in the tanker body frame (x forward, y left, z up, "
                  "metres). Rotations are tanker_from_camera: columns are the camera's x (right), y (down), z "
                  "(optical axis) expressed in the tanker frame.";
  return r;
}

}  // namespace

RigPreset Rig1080p() { return WideRig(1920, 1080, "1080p"); }

RigPreset Rig2160p() { return WideRig(3840, 2160, "2160p (4K UHD)"); }

RigPreset NoisyRig() {
  RigPreset r = DefaultRig();
  // A machine-vision CMOS sensor (SensorParams' defaults: 10,000 e- full
  // well, 6 e- read noise, 1 % PRNU, 2 e- DSNU, 12-bit ADC) exposed so that
  // radiance 1.0 collects 2,000 e- (the sky's blue channel 1,560 e-: SNR 39 from
  // shot noise alone, 36 with the rest), a blur of 0.5 px and an RGGB mosaic.
  SensorParams sensor;
  sensor.exposure_e = 2000.0;
  sensor.blur_sigma_px = 0.5;
  sensor.bayer = BayerPattern::kRggb;
  r.sensor = sensor;
  r.description =
      "The cameras of scenes/rig.json with an image sensor (issue 9, item 4): EMVA 1288 photon transfer (exposure, "
      "shot and read noise, fixed-pattern noise, full well, 12-bit ADC), a Gaussian optical blur and an RGGB Bayer "
      "mosaic, docs/rendering.md. Positions in the tanker body frame (x forward, y left, z up, metres). Rotations are "
      "tanker_from_camera: columns are the camera's x (right), y (down), z (optical axis) expressed in the tanker "
      "frame.";
  return r;
}

RigPreset LwirRig() {
  RigPreset r = DefaultRig();
  const RigPreset base;
  // An uncooled microbolometer of the 640 x 512 class (12 um pixels): NETD
  // 50 mK and a residual fixed pattern of 25 mK after its non-uniformity
  // correction, the order of data sheets for such cores; the lens gives
  // rig.json's vertical field of view (46.2 deg), so 600 px.
  r.image_width = 640;
  r.image_height = 512;
  r.f_px = base.f_px * 512 / base.image_height;
  r.cx_px = 319.5;
  r.cy_px = 255.5;
  ThermalCamera lwir;
  lwir.netd_mk = 50.0;
  lwir.nonuniformity_mk = 25.0;
  r.lwir = lwir;
  r.description =
      "A long-wave infrared (8-14 um) stereo pair in the place of scenes/rig.json's cameras, with their vertical field "
      "of view at 640 x 512: NETD 50 mK, a 25 mK fixed pattern; radiometric 16-bit images, docs/rendering.md, "
      "section Thermal camera. Positions in the tanker body frame (x forward, y left, z up, metres). Rotations are "
      "tanker_from_camera: columns are the camera's x (right), y (down), z (optical axis) expressed in the tanker "
      "frame.";
  return r;
}

RigPreset RollingRig() {
  RigPreset r = NoisyRig();
  // The same sensor read out row by row over 30 ms: a CMOS rolling shutter of
  // the order machine-vision data sheets give for a megapixel sensor at
  // 30 frames/s (about 40 us a row at 768 rows).
  r.sensor->readout_ms = 30.0;
  r.description =
      "The cameras and sensor of scenes/rig-noisy.json with a rolling shutter: rows exposed top to bottom over a 30 ms "
      "readout (sensor.readout_ms), docs/rendering.md. Positions in the tanker body frame (x forward, y left, z up, "
      "metres). Rotations are tanker_from_camera: columns are the camera's x (right), y (down), z (optical axis) "
      "expressed in the tanker frame.";
  return r;
}

std::string FormatRig(const RigPreset& r) {
  double c = 0.0, s = 0.0;
  CosSinDeg(r.contact_depression_deg, &c, &s);
  const double contact_x = r.centre_m[0] - r.contact_range_m * c;
  const double contact_z = r.centre_m[2] - r.contact_range_m * s;
  std::ostringstream o;
  o << "{\n"
    << "  \"schema\": \""
    << (r.lwir         ? "aar-rig/4"
        : r.sensor     ? "aar-rig/3"
        : Distorted(r) ? "aar-rig/2"
                       : "aar-rig/1")
    << "\",\n"
    << "  \"description\": \"" << r.description << "\",\n"
    << "  \"image_width\": " << r.image_width << ",\n"
    << "  \"image_height\": " << r.image_height << ",\n"
    << "  \"cameras\": {\n"
    << "    \"left\": {\n"
    << Camera(r, -r.half_baseline_m, r.left_distortion) << "    },\n"
    << "    \"right\": {\n"
    << Camera(r, r.half_baseline_m, r.right_distortion) << "    }\n"
    << "  },\n"
    << (r.sensor ? Sensor(*r.sensor) : "") << (r.lwir ? Lwir(*r.lwir) : "") << "  \"near_m\": " << Num(r.near_m)
    << ",\n"
    << "  \"contact_position_m\": [" << Num(contact_x) << ", " << Num(r.centre_m[1]) << ", " << Num(contact_z) << "]\n"
    << "}\n";
  return o.str();
}

}  // namespace aar::scenes
