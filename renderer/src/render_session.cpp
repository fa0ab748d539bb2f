#include "aar/renderer/render_session.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/progress.h"
#include "aar/renderer/dataset_writer.h"
#include "aar/renderer/daylight.h"
#include "aar/text.h"

namespace aar {
namespace {

nlohmann::json DeviceJson(const DeviceInfo& d) {
  return {{"name", d.name},
          {"driver_name", d.driver_name},
          {"driver_info", d.driver_info},
          {"api_version", d.api_version},
          {"vendor_id", d.vendor_id},
          {"device_id", d.device_id},
          {"type", d.device_type},
          {"standard_sample_locations", d.standard_sample_locations}};
}

// Both cameras' pinhole stand-ins share one image size: the union of the margins they need.
void OpenLenses(RenderSession& s) {
  if (!HasDistortion(s.rig)) return;
  PixelMargin margin;
  for (const char* side : {"left", "right"}) {
    const PixelMargin m =
        LensResampler::RequiredMargin(s.RigCamera(side).intrinsics, std::string("rig camera ") + side);
    margin = {std::max(margin.left, m.left), std::max(margin.top, m.top), std::max(margin.right, m.right),
              std::max(margin.bottom, m.bottom)};
  }
  s.left_lens.emplace(s.rig.left.intrinsics, margin, "rig camera left");
  s.right_lens.emplace(s.rig.right.intrinsics, margin, "rig camera right");
}

nlohmann::json LensJson(const RenderSession& s) {
  const auto coefficients = [](const Intrinsics& k) {
    const std::array<double, 5> d = k.distortion.OpenCvOrder();
    return nlohmann::json(std::vector<double>(d.begin(), d.end()));
  };
  const Intrinsics& pinhole = s.left_lens->pinhole();
  return {{"model", "brown-conrady: OpenCV k1, k2, p1, p2, k3"},
          {"left", coefficients(s.rig.left.intrinsics)},
          {"right", coefficients(s.rig.right.intrinsics)},
          {"pinhole_render",
           {{"width", pinhole.width_px},
            {"height", pinhole.height_px},
            {"margin_left_top_px",
             {pinhole.cx_px - s.rig.left.intrinsics.cx_px, pinhole.cy_px - s.rig.left.intrinsics.cy_px}}}},
          {"color_resampling",
           "inverse map (Newton), separable Lanczos-3 in linear float colour, footprint scaled by the inverse map's "
           "Jacobian (at least one pinhole pixel), negative lobes clamped at 0"},
          {"truth_resampling", "nearest pinhole sample (depth, object ids, silhouette never blended)"}};
}

nlohmann::json SensorJson(const SensorParams& sensor) {
  nlohmann::json j = SensorToJson(sensor);
  j["gain_dn_per_e"] = sensor.GainDnPerElectron();
  j["model"] =
      "EMVA 1288 photon transfer per pixel and channel (per pixel under the mosaic): electrons = radiance * "
      "exposure_e * (1 + prnu * n_pixel), shot noise as its Gaussian approximation N(mean, mean), clipped at "
      "full_well_e, plus dsnu_e * n_pixel and read_noise_e * n; DN = round(K * electrons + black_level_dn) in "
      "[0, 2^adc_bits - 1]; written as (DN - black_level_dn) / (K * exposure_e)";
  j["optics"] = "Gaussian PSF, sigma blur_sigma_px, cut at 3 sigma, in linear light before the noise";
  if (sensor.blooming > 0.0 || sensor.smear > 0.0) {
    j["charge_spill"] =
        "on the mean electrons before the shot noise, per column (of each channel; of the mosaic): + smear * the "
        "column's mean, then blooming * each pixel's excess over full_well_e spilled half up and half down, filling "
        "each neighbour to full_well_e before going on, lost past the image's edge; the rest of the excess drained";
  }
  if (!sensor.flare_ghosts.empty()) {
    j["lens_flare"] =
        "ghosts of the sun on the pinhole render: discs of radius_px at c + position (s - c), c the principal point, "
        "s the sun's projection, each spreading fraction x pi S cos(alpha) uniformly over its solid angle, before "
        "the exposure, lens and sensor";
  }
  j["demosaicing"] = sensor.bayer == BayerPattern::kNone ? "none" : "bilinear";
  j["noise"] =
      "counter-based: splitmix64 of (seed, stream, frames 0 / calib 1, index, camera 0 left / 1 right, sample), "
      "Box-Muller; the fixed pattern of (seed, camera, sample) alone";
  return j;
}

// Depth truth of one camera at one instant: depth and object ids from a
// single-sample pass of the whole scene, and the receiver's silhouette from
// a pass of the receiver alone (255 where it covers the pixel, whatever is in
// front); of `rows` only when given. Before the lens's resampling.
ViewTruth RenderTruthPasses(RenderSession& session, const std::vector<RenderItem>& items, const std::string& side,
                            const PixelRect* rows) {
  const Camera camera = session.RenderCamera(side);
  ViewTruth view;
  view.side = side;
  view.scene = session.renderer->RenderGroundTruth(camera, session.rig.near_m, items, rows);
  std::vector<RenderItem> receiver_only;
  for (const RenderItem& item : items) {
    if (item.object_id == kReceiverObjectId) receiver_only.push_back(item);
  }
  view.alone = session.renderer->RenderGroundTruth(camera, session.rig.near_m, receiver_only, rows);
  return view;
}

// Depth truth of one camera: of the one band's instant, or of each readout
// band's in its own pixels; resampled through the lens.
ViewTruth RenderDepthTruth(RenderSession& session, const std::vector<BandScene>& bands, const std::string& side,
                           RenderStageTimes& times) {
  auto start = std::chrono::steady_clock::now();
  const std::optional<ReadoutBands>& readout = session.Readout(side);
  ViewTruth view =
      RenderTruthPasses(session, bands.front().instant, side, bands.size() > 1 ? &readout->Rows(0) : nullptr);
  for (size_t b = 1; b < bands.size(); ++b) {
    const ViewTruth band = RenderTruthPasses(session, bands[b].instant, side, &readout->Rows(static_cast<int>(b)));
    readout->Composite(static_cast<int>(b), band.scene, view.scene);
    readout->Composite(static_cast<int>(b), band.alone, view.alone);
  }
  times.render_ms += MillisecondsSince(start);
  if (const std::optional<LensResampler>& lens = session.Lens(side)) {
    start = std::chrono::steady_clock::now();
    view.scene = lens->ResampleTruth(view.scene);
    view.alone = lens->ResampleTruth(view.alone);
    times.readback_ms += MillisecondsSince(start);
  }
  return view;
}

// Linear colour of one camera: the one band's exposure, or each readout
// band's in its own pixels (band 0's render holds the background elsewhere,
// which the other bands' pixels replace).
LinearImage RenderViewColor(RenderSession& session, const std::vector<BandScene>& bands, const std::string& side,
                            RenderStageTimes& times) {
  const Camera camera = session.RenderCamera(side);
  const std::optional<ReadoutBands>& readout = session.Readout(side);
  ViewTimings timings;
  LinearImage color = session.renderer->RenderExposure(camera, session.rig.near_m, bands.front().exposure, session.plan,
                                                       &timings, bands.size() > 1 ? &readout->Rows(0) : nullptr);
  for (size_t b = 1; b < bands.size(); ++b) {
    const LinearImage band = session.renderer->RenderExposure(
        camera, session.rig.near_m, bands[b].exposure, session.plan, &timings, &readout->Rows(static_cast<int>(b)));
    readout->Composite(static_cast<int>(b), band, color);
  }
  times.render_ms += timings.render_ms;
  times.readback_ms += timings.readback_ms;
  return color;
}

}  // namespace

RenderSession OpenRenderSession(const RenderJobOptions& options, const StereoRig& rig,
                                const BackgroundOptions& background, const SessionLighting& lighting) {
  RenderSession s;
  s.rig = rig;
  if (rig.sensor) s.sensor = std::make_shared<const SensorModel>(*rig.sensor);
  if (rig.lwir) {
    s.thermal = std::make_shared<const ThermalScene>(*rig.lwir, options.thermal.value_or(ThermalSceneOptions{}),
                                                     background.altitude_m);
    s.thermal_sensor = std::make_shared<const ThermalSensor>(s.thermal);
  }
  VulkanContextOptions vk;
  vk.device_filter = options.device;
  s.context = std::make_unique<VulkanContext>(vk);
  s.plan = PlanMsaa(options.msaa, s.context->info().color_sample_counts);
  SceneRendererOptions render_options;
  render_options.max_anisotropy = options.anisotropy;
  render_options.background = background;
  if (s.thermal) render_options.sky_linear.fill(static_cast<float>(s.thermal->sky_radiance));
  render_options.shading = lighting.shading;
  render_options.shadows = lighting.shadows;
  render_options.floodlight = lighting.floodlight;
  s.floodlight = lighting.floodlight;
  render_options.shadow_object_id = kReceiverObjectId;
  OpenLenses(s);
  if (rig.sensor && rig.sensor->readout_ms > 0.0) {
    s.readout_ms = rig.sensor->readout_ms;
    s.left_readout.emplace(rig.left.intrinsics, s.RenderCamera("left").intrinsics, options.readout_bands);
    s.right_readout.emplace(rig.right.intrinsics, s.RenderCamera("right").intrinsics, options.readout_bands);
  }
  if (rig.sensor && (rig.sensor->glare_fraction > 0.0 || !rig.sensor->flare_ghosts.empty())) {
    const Eigen::Vector3d sun = LevelFromTanker(background).transpose() * SunInLevel(background);
    const Eigen::Vector3d light = SunLightAtTanker(background);
    for (const std::string side : {"left", "right"}) {
      if (rig.sensor->glare_fraction > 0.0) {
        (side == "left" ? s.left_glare : s.right_glare)
            .emplace(s.RenderCamera(side), sun, light, rig.sensor->glare_fraction, rig.sensor->glare_core_deg);
      }
      if (!rig.sensor->flare_ghosts.empty()) {
        (side == "left" ? s.left_flare : s.right_flare)
            .emplace(s.RenderCamera(side), sun, light, rig.sensor->flare_ghosts);
      }
    }
  }
  if (lighting.exposure_ev != 0.0 || RenderScale(background) != 1.0) {
    s.exposure.emplace(lighting.exposure_ev, RenderScale(background));
  }
  const Intrinsics& size = s.RenderCamera("left").intrinsics;
  s.renderer = std::make_unique<SceneRenderer>(*s.context, size.width_px, size.height_px, render_options);
  return s;
}

RenderedPair RenderPair(RenderSession& session, const std::vector<BandScene>& bands, const std::string& dir,
                        FrameSidecar sidecar, const std::vector<std::string>& depth_sides, RenderStageTimes& times) {
  const size_t readout_bands = session.left_readout ? static_cast<size_t>(session.left_readout->bands()) : 1;
  if (bands.empty() || (bands.size() > 1 && bands.size() != readout_bands)) {
    throw Error("render: " + std::to_string(bands.size()) + " bands of a pair, the session reads out " +
                std::to_string(readout_bands));
  }
  RenderedPair pair;
  pair.dir = dir;
  pair.sidecar = std::move(sidecar);
  for (size_t view = 0; view < pair.color.size(); ++view) {
    const std::string side = view == 0 ? "left" : "right";
    pair.color[view] = RenderViewColor(session, bands, side, times);
    // Applied on the writer's threads, beside the next pair's rendering.
    pair.effects[view] = session.ViewEffects(side);
  }
  pair.radiometric = session.thermal != nullptr;
  for (const std::string& side : depth_sides) pair.truth.push_back(RenderDepthTruth(session, bands, side, times));
  return pair;
}

nlohmann::json MsaaJson(const MsaaPlan& plan) {
  nlohmann::json offsets = nlohmann::json::array();
  for (const Vec2& o : plan.offsets_px) offsets.push_back({o.x, o.y});
  nlohmann::json pattern = nlohmann::json::array();
  for (const Vec2& s : CompositeSamplePattern(plan)) pattern.push_back({s.x, s.y});
  return {{"level", plan.level},
          {"method", plan.method},
          {"native_samples", plan.native_samples},
          {"passes", plan.passes},
          {"pass_offsets_px", offsets},
          {"sample_positions_px", pattern},
          {"averaging", "hardware resolve per pass, then mean of passes, in linear float colour"}};
}

nlohmann::json SessionManifestHeader(const RenderSession& session, const std::string& rig_hash) {
  nlohmann::json header = {{"schema", kDatasetSchema},
                           {"renderer", RendererIdentity()},
                           {"device", DeviceJson(session.context->info())},
                           {"image",
                            {{"width", session.rig.left.intrinsics.width_px},
                             {"height", session.rig.left.intrinsics.height_px},
                             {"encoding", "PNG, 8-bit sRGB, RGB"}}},
                           {"inputs", {{"rig", {{"file", kRigName}, {"sha256", rig_hash}}}}}};
  if (session.left_lens) header["image"]["lens"] = LensJson(session);                   // absent for a pinhole rig
  if (session.rig.sensor) header["image"]["sensor"] = SensorJson(*session.rig.sensor);  // absent: the ideal sensor
  if (session.thermal) {
    header["image"]["encoding"] = "PNG, 16-bit, one channel: brightness temperature x 100 [0.01 K]";
    header["image"]["lwir"] = ThermalToJson(*session.rig.lwir);
    header["image"]["lwir"]["noise"] =
        "radiance + netd_mk x dL/dT(300 K) x n (seed, frames 0 / calib 1, index, camera, pixel) + nonuniformity_mk x "
        "dL/dT(300 K) x m (seed, camera, pixel), then the band's brightness temperature (thermal_sensor.h)";
  }
  return header;
}

}  // namespace aar
