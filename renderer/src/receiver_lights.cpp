#include "aar/renderer/receiver_lights.h"

#include <cmath>
#include <numbers>

#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/renderer/daylight.h"

namespace aar {
namespace {

constexpr double kPi = std::numbers::pi;

// Linear sRGB of chromaticity (x, y) scaled to unit luminance, clipped to
// the gamut (the aviation colours lie outside it).
Eigen::Vector3d ColorOfChromaticity(double x, double y) {
  const Eigen::Vector3d rgb = LinearSrgbFromXyz(Eigen::Vector3d(x / y, 1.0, (1.0 - x - y) / y)).cwiseMax(0.0);
  return rgb / Eigen::Vector3d(0.2126, 0.7152, 0.0722).dot(rgb);
}

// The airframe's vertex farthest along `axis`.
Eigen::Vector3d Outermost(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& axis) {
  Eigen::Vector3d best = points.front();
  for (const Eigen::Vector3d& p : points) {
    if (p.dot(axis) > best.dot(axis)) best = p;
  }
  return best;
}

// A flash of peak intensity I for t seconds has the effective intensity
// I t / (0.2 + t) (Blondel-Rey); the peak that gives `effective_cd`.
double PeakOfFlash(double effective_cd, double on_s) { return effective_cd * (0.2 + on_s) / on_s; }

}  // namespace

bool ReceiverLight::OnAt(double time_s) const {
  if (period_s <= 0.0) return true;
  const double t = std::fmod(time_s - phase_s, period_s);
  return (t < 0.0 ? t + period_s : t) < on_s;
}

Eigen::Vector3d ReceiverLight::Radiance(double render_scale) const {
  const double units_per_candela = 0.75 * kPi / kSolarIlluminanceLx;
  return color * (intensity_cd / (kPi * radius_m * radius_m) * units_per_candela * render_scale);
}

std::vector<ReceiverLight> ReceiverLightsOf(const SceneModel& airframe) {
  const std::vector<Eigen::Vector3d> points = airframe.AllPositions();
  if (points.empty()) throw Error(airframe.path.string() + ": no vertices to place the receiver's lights on");
  // Aviation red, green and white (14 CFR 23.1397): chromaticities inside their limits.
  const Eigen::Vector3d red = ColorOfChromaticity(0.690, 0.308);
  const Eigen::Vector3d green = ColorOfChromaticity(0.170, 0.700);
  const Eigen::Vector3d white = ColorOfChromaticity(0.3127, 0.3290);
  // Position lights at their minimum intensities ahead and astern (23.1395):
  // 40 cd red and green, 20 cd white. Anti-collision lights: 400 cd
  // effective (23.1401) at 60 flashes a minute (40 to 100 allowed): the
  // beacons 0.1 s flashes, the strobes 0.05 s half a period later.
  struct Placement {
    const char* name;
    Eigen::Vector3d axis;
    double aft_m;  // the strobes: one diameter aft of the position light
    Eigen::Vector3d color;
    double effective_cd, on_s, phase_s;  // on_s 0: steady
  };
  const double r = 0.04;
  const Eigen::Vector3d left(0, 1, 0), right(0, -1, 0), aft(-1, 0, 0), up(0, 0, 1), down(0, 0, -1);
  const std::vector<Placement> placements = {{"position_left_red", left, 0.0, red, 40.0, 0.0, 0.0},
                                             {"position_right_green", right, 0.0, green, 40.0, 0.0, 0.0},
                                             {"position_tail_white", aft, 0.0, white, 20.0, 0.0, 0.0},
                                             {"beacon_top_red", up, 0.0, red, 400.0, 0.1, 0.0},
                                             {"beacon_bottom_red", down, 0.0, red, 400.0, 0.1, 0.0},
                                             {"strobe_left_white", left, 2.0 * r, white, 400.0, 0.05, 0.5},
                                             {"strobe_right_white", right, 2.0 * r, white, 400.0, 0.05, 0.5}};
  std::vector<ReceiverLight> lights;
  for (const Placement& p : placements) {
    ReceiverLight light;
    light.name = p.name;
    light.position_in_receiver = Outermost(points, p.axis) + r * p.axis;
    light.position_in_receiver.x() -= p.aft_m;
    light.color = p.color;
    light.radius_m = r;
    light.intensity_cd = p.on_s > 0.0 ? PeakOfFlash(p.effective_cd, p.on_s) : p.effective_cd;
    if (p.on_s > 0.0) {
      light.period_s = 1.0;
      light.on_s = p.on_s;
      light.phase_s = p.phase_s;
    }
    lights.push_back(light);
  }
  return lights;
}

SceneModel LightSphereModel(const ReceiverLight& light, double render_scale) {
  constexpr int kRings = 8, kSegments = 16;
  Primitive p;
  for (int i = 0; i <= kRings; ++i) {
    const double theta = kPi * i / kRings;
    for (int j = 0; j <= kSegments; ++j) {
      const double phi = 2.0 * kPi * j / kSegments;
      const Eigen::Vector3d n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const Eigen::Vector3f v = (light.radius_m * n).cast<float>();
      const Eigen::Vector3f nf = n.cast<float>();
      p.vertices.push_back({{v.x(), v.y(), v.z()}, {nf.x(), nf.y(), nf.z()}, {0.0f, 0.0f}});
    }
  }
  for (int i = 0; i < kRings; ++i) {
    for (int j = 0; j < kSegments; ++j) {
      const uint32_t a = i * (kSegments + 1) + j, b = a + kSegments + 1;
      p.indices.insert(p.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
  const Eigen::Vector3d radiance = light.Radiance(render_scale);
  p.base_color_factor = {static_cast<float>(radiance.x()), static_cast<float>(radiance.y()),
                         static_cast<float>(radiance.z()), 1.0f};
  p.emissive = true;
  SceneModel model;
  model.path = "receiver light " + light.name;
  model.primitives.push_back(std::move(p));
  return model;
}

nlohmann::json ReceiverLightsJson(const std::vector<ReceiverLight>& lights) {
  nlohmann::json list = nlohmann::json::array();
  for (const ReceiverLight& l : lights) {
    nlohmann::json j = {{"name", l.name},
                        {"position_in_receiver_m",
                         {l.position_in_receiver.x(), l.position_in_receiver.y(), l.position_in_receiver.z()}},
                        {"color_linear_srgb", {l.color.x(), l.color.y(), l.color.z()}},
                        {"intensity_cd", l.intensity_cd},
                        {"radius_m", l.radius_m}};
    if (l.period_s > 0.0) j["flash"] = {{"period_s", l.period_s}, {"on_s", l.on_s}, {"phase_s", l.phase_s}};
    list.push_back(j);
  }
  return {{"lights", list},
          {"mask_id", kReceiverLightsMaskId},
          {"model",
           "spheres of uniform radiance intensity / (pi r^2) at the airframe's outermost vertices; flashing lights "
           "on while (time - phase) mod period < on; 14 CFR 23.1391-23.1401 minimum intensities, the flashes' "
           "peak from 400 cd effective (Blondel-Rey)"}};
}

}  // namespace aar
