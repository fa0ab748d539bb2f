#include "aar/renderer/stereo_render_job.h"

#include <unistd.h>

#include <chrono>
#include <optional>
#include <tuple>

#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/flight_path.h"
#include "aar/progress.h"
#include "aar/region.h"
#include "aar/renderer/calib_poses.h"
#include "aar/renderer/dataset_writer.h"
#include "aar/renderer/exposure.h"
#include "aar/renderer/lens_distortion.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/pair_writer.h"
#include "aar/renderer/projection.h"
#include "aar/renderer/scene_renderer.h"
#include "aar/renderer/sensor_model.h"
#include "aar/stereo_calibration.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr float kReceiverId = 1.0f;
constexpr float kTankerId = 2.0f;
constexpr float kBoardId = 3.0f;
constexpr float kBoomId = static_cast<float>(kBoomMaskId);

// Fails before anything is written when `dir` cannot be created or written.
void CheckDatasetFolderWritable(const std::filesystem::path& dir) {
  if (dir.empty()) throw Error("no output folder given");
  std::filesystem::path probe = std::filesystem::absolute(dir);
  while (!std::filesystem::exists(probe) && probe.has_parent_path() && probe != probe.parent_path()) {
    probe = probe.parent_path();
  }
  if (!std::filesystem::is_directory(probe)) {
    throw Error(dir.string() + ": cannot create output folder ('" + probe.string() + "' is not a folder)");
  }
  if (::access(probe.c_str(), W_OK) != 0) throw Error(dir.string() + ": output folder is not writable");
}

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

struct Session {
  StereoRig rig;
  std::unique_ptr<VulkanContext> context;
  std::unique_ptr<SceneRenderer> renderer;
  MsaaPlan plan;
  // With lens distortion (docs/rendering.md): both cameras are rendered as
  // pinhole cameras on one grown image and resampled; empty for a pinhole rig.
  std::optional<LensResampler> left_lens, right_lens;
  // The rig's sensor, its fixed patterns drawn once for the whole run; null without one.
  std::shared_ptr<const SensorModel> sensor;

  const Camera& RigCamera(const std::string& side) const { return side == "left" ? rig.left : rig.right; }
  const std::optional<LensResampler>& Lens(const std::string& side) const {
    return side == "left" ? left_lens : right_lens;
  }
  /// The camera the scene is rendered with: the rig's, or its pinhole stand-in.
  Camera RenderCamera(const std::string& side) const {
    Camera camera = RigCamera(side);
    if (Lens(side)) camera.intrinsics = Lens(side)->pinhole();
    return camera;
  }
};

// Both cameras' pinhole stand-ins share one image size: the union of the margins they need.
void OpenLenses(Session& s) {
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

nlohmann::json LensJson(const Session& s) {
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
  j["demosaicing"] = sensor.bayer == BayerPattern::kNone ? "none" : "bilinear";
  j["noise"] =
      "counter-based: splitmix64 of (seed, stream, frames 0 / calib 1, index, camera 0 left / 1 right, sample), "
      "Box-Muller; the fixed pattern of (seed, camera, sample) alone";
  return j;
}

Session OpenSession(const RenderJobOptions& options, const StereoRig& rig, const BackgroundOptions& background) {
  Session s;
  s.rig = rig;
  if (rig.sensor) s.sensor = std::make_shared<const SensorModel>(*rig.sensor);
  VulkanContextOptions vk;
  vk.device_filter = options.device;
  s.context = std::make_unique<VulkanContext>(vk);
  s.plan = PlanMsaa(options.msaa, s.context->info().color_sample_counts);
  SceneRendererOptions render_options;
  render_options.max_anisotropy = options.anisotropy;
  render_options.background = background;
  OpenLenses(s);
  const Intrinsics& size = s.RenderCamera("left").intrinsics;
  s.renderer = std::make_unique<SceneRenderer>(*s.context, size.width_px, size.height_px, render_options);
  return s;
}

// Depth truth of one camera: depth and object ids from a single-sample pass
// of the whole scene, and the receiver's silhouette from a pass of the
// receiver alone (255 where it covers the pixel, whatever is in front).
ViewTruth RenderDepthTruth(Session& session, const std::vector<RenderItem>& items, const std::string& side,
                           RenderStageTimes& times) {
  const Camera camera = session.RenderCamera(side);
  auto start = std::chrono::steady_clock::now();
  ViewTruth view;
  view.side = side;
  view.scene = session.renderer->RenderGroundTruth(camera, session.rig.near_m, items);
  std::vector<RenderItem> receiver_only;
  for (const RenderItem& item : items) {
    if (item.object_id == kReceiverId) receiver_only.push_back(item);
  }
  view.alone = session.renderer->RenderGroundTruth(camera, session.rig.near_m, receiver_only);
  times.render_ms += MillisecondsSince(start);
  if (const std::optional<LensResampler>& lens = session.Lens(side)) {
    start = std::chrono::steady_clock::now();
    view.scene = lens->ResampleTruth(view.scene);
    view.alone = lens->ResampleTruth(view.alone);
    times.readback_ms += MillisecondsSince(start);
  }
  return view;
}

// Renders one stereo pair (and the truth asked for); the PairWriter encodes and writes it.
// The colour is exposed over `exposure` (the scene at each instant; one
// instant: no motion), the truth is of `items` (the sample's own time).
RenderedPair RenderPair(Session& session, const std::vector<std::vector<RenderItem>>& exposure,
                        const std::vector<RenderItem>& items, const std::string& dir, FrameSidecar sidecar,
                        const std::vector<std::string>& depth_sides, RenderStageTimes& times) {
  RenderedPair pair;
  pair.dir = dir;
  pair.sidecar = std::move(sidecar);
  pair.sensor = session.sensor;
  for (size_t view = 0; view < pair.color.size(); ++view) {
    const std::string side = view == 0 ? "left" : "right";
    ViewTimings timings;
    pair.color[view] = session.renderer->RenderExposure(session.RenderCamera(side), session.rig.near_m, exposure,
                                                        session.plan, &timings);
    times.render_ms += timings.render_ms;
    times.readback_ms += timings.readback_ms;
    // Resampled through the lens on the writer's threads, beside the next pair's rendering.
    if (const std::optional<LensResampler>& lens = session.Lens(side)) pair.lens[view] = &*lens;
  }
  for (const std::string& side : depth_sides) pair.truth.push_back(RenderDepthTruth(session, items, side, times));
  return pair;
}

// Shared loop: renders the selected pairs not yet complete, then finalizes.
template <typename MakePair>
RenderJobResult RunPairs(const RenderJobOptions& options, Session& session, size_t count, const std::string& kind,
                         const std::string& settings, const std::string& label, MakePair make_pair) {
  RenderJobResult result;
  result.msaa_method = session.plan.method;
  result.device = session.context->info().name;
  const std::vector<size_t> selected = options.selection.Select(count);
  result.selected = selected.size();
  const std::string dir = kind == "calib" ? kCalibDir : kFramesDir;
  EnsureWritableDirectory(options.output / dir);
  std::vector<std::string> depth_sides;
  if (kind == "frame" && (options.depth || options.depth_right)) depth_sides.push_back("left");
  if (kind == "frame" && options.depth_right) depth_sides.push_back("right");
  Progress progress(label, selected.size());
  const auto start = std::chrono::steady_clock::now();
  // Pair k is encoded and written while pair k + 1 renders.
  PairWriterOptions writing;
  // Texture behind the receiver or sensor noise: deflate finds few matches, so the fast settings.
  if ((options.background.enabled() && kind == "frame") || session.sensor) writing.color_png = PngStrategy::kFast;
  PairWriter writer(options.output, writing);
  for (size_t index : selected) {
    if (SidecarVerified(options.output, SidecarPath(options.output, kind, index), settings)) {
      ++result.skipped;
    } else {
      auto [exposure, items, sidecar] = make_pair(index);
      writer.Push(RenderPair(session, exposure, items, dir, std::move(sidecar), depth_sides, result.times));
      ++result.rendered;
    }
    if (options.progress) progress.Advance();
  }
  const PairWriteTimes written = writer.Finish();
  result.times.encode_ms = written.encode_ms;
  result.times.write_ms = written.write_ms;
  result.times.wait_ms = writer.wait_ms();
  result.times.wall_ms = MillisecondsSince(start);
  if (options.progress) progress.Finish();
  result.complete = FinalizeManifest(options.output);
  return result;
}

// The rig's exact calibration; throws, naming the rig file and writing
// nothing, for a rig it cannot describe.
StereoCalibration IdealCalibrationOf(const StereoRig& rig, const std::filesystem::path& rig_path) {
  try {
    return IdealCalibration(rig);
  } catch (const Error& e) {
    throw Error(rig_path.string() + ": " + e.what());
  }
}

// frames.boom of the manifest: where the boom's pose comes from and its frame.
nlohmann::json BoomJson(bool posed_by_path) {
  return {{"mask_id", kBoomMaskId},
          {"pose", posed_by_path ? "flight-path columns boom_pitch_deg, boom_roll_deg, boom_extension_m"
                                 : "defaults (stowed): boom_pitch_deg 0, boom_roll_deg 0, boom_extension_m 0"},
          {"hinge_in_tanker_m", {kBoomHingeInTanker.x(), kBoomHingeInTanker.y(), kBoomHingeInTanker.z()}},
          {"tanker_from_boom", "Translation(hinge) * Rx(roll) * Ry(-pitch); the boom along -x of its frame"},
          {"tanker_from_boom_tube", "tanker_from_boom * Translation(-extension_m, 0, 0)"}};
}

// The manifest keys both jobs share; computes hashes, writes nothing.
nlohmann::json CommonHeader(const Session& session, const std::string& rig_hash) {
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
  return header;
}

// The models of a flight-path job: the receiver, the tanker, the boom and
// its tube (with_boom) and the propeller (with_propellers).
struct FlightPathModels {
  SceneModel receiver, tanker;
  bool with_boom = false, with_propellers = false;
  std::optional<SceneModel> boom, boom_tube, propeller;
};

FlightPathModels LoadFlightPathModels(const RenderJobOptions& options, const std::vector<FlightSample>& path) {
  FlightPathModels models;
  models.receiver = LoadSceneModel(options.receiver_model);
  models.tanker = LoadSceneModel(options.tanker_model);
  // The boom: posed by the path's columns, or stowed on a 7-column path with --boom.
  models.with_boom = options.boom || path.front().boom.has_value();
  if (models.with_boom) {
    models.boom = LoadSceneModel(options.boom_model);
    models.boom_tube = LoadSceneModel(options.boom_tube_model);
  }
  models.with_propellers = options.propeller_rpm > 0.0;
  if (models.with_propellers) models.propeller = LoadSceneModel(options.propeller_model);
  return models;
}

// The flight-path models' indices on the renderer; -1 for the boom's without it.
struct FlightPathModelIndices {
  ReceiverModels receiver;
  int tanker = -1, boom = -1, boom_tube = -1;
};

// Adds the models to the session's renderer: receiver, tanker, boom, boom tube, propeller.
FlightPathModelIndices AddFlightPathModels(Session& session, const FlightPathModels& models) {
  FlightPathModelIndices indices;
  indices.receiver.airframe = session.renderer->AddModel(models.receiver);
  indices.receiver.object_id = kReceiverId;
  indices.tanker = session.renderer->AddModel(models.tanker);
  indices.boom = models.with_boom ? session.renderer->AddModel(*models.boom) : -1;
  indices.boom_tube = models.with_boom ? session.renderer->AddModel(*models.boom_tube) : -1;
  if (models.with_propellers) indices.receiver.propeller = session.renderer->AddModel(*models.propeller);
  return indices;
}

// Hashes of the inputs a flight-path dataset keeps a copy of; the boom's empty without it.
struct FlightPathInputHashes {
  std::string rig, receiver, path, boom, boom_tube;
};

struct FlightPathManifest {
  nlohmann::json header;
  FlightPathInputHashes hashes;
};

// frames of the manifest: how every frame of the flight path is rendered.
nlohmann::json FlightPathFramesJson(const RenderJobOptions& options, const MsaaPlan& plan,
                                    const std::vector<FlightSample>& path, const FlightPathModels& models) {
  nlohmann::json frames = {{"count", path.size()},
                           {"msaa", MsaaJson(plan)},
                           {"depth", options.depth || options.depth_right},
                           {"depth_right", options.depth_right},
                           {"texture_anisotropy", options.anisotropy}};
  // Absent for the flat sky, so datasets made before backgrounds existed still match.
  if (options.background.enabled()) frames["background"] = BackgroundJson(options.background);
  // Absent without the boom, so datasets without it keep their bytes.
  if (models.with_boom) frames["boom"] = BoomJson(path.front().boom.has_value());
  // Absent for an instant exposure and without propellers, likewise.
  if (options.shutter_ms > 0.0) frames["exposure"] = ExposureJson(options.shutter_ms, options.time_samples);
  if (models.with_propellers) frames["propellers"] = PropellersJson(options.propeller_rpm);
  return frames;
}

// The manifest header of a flight-path job; hashes its inputs, writes nothing.
FlightPathManifest FlightPathManifestHeader(const RenderJobOptions& options, const Session& session,
                                            const FlightPathModels& models, const std::vector<FlightSample>& path) {
  FlightPathManifest manifest;
  FlightPathInputHashes& hashes = manifest.hashes;
  hashes.rig = Sha256File(options.rig);
  hashes.receiver = Sha256File(options.receiver_model);
  hashes.path = Sha256File(options.flight_path);
  nlohmann::json& header = manifest.header;
  header = CommonHeader(session, hashes.rig);
  header["inputs"]["receiver_model"] = {{"file", kReceiverModelName}, {"sha256", hashes.receiver}};
  header["inputs"]["tanker_model"] = {{"source", options.tanker_model.filename().string()},
                                      {"sha256", Sha256File(options.tanker_model)}};
  header["inputs"]["flight_path"] = {{"file", kFlightPathName}, {"sha256", hashes.path}};
  if (models.with_boom) {
    hashes.boom = Sha256File(options.boom_model);
    hashes.boom_tube = Sha256File(options.boom_tube_model);
    header["inputs"]["boom_model"] = {{"file", kBoomModelName}, {"sha256", hashes.boom}};
    header["inputs"]["boom_tube_model"] = {{"file", kBoomTubeModelName}, {"sha256", hashes.boom_tube}};
  }
  if (models.with_propellers) {
    header["inputs"]["propeller_model"] = {{"source", options.propeller_model.filename().string()},
                                           {"sha256", Sha256File(options.propeller_model)}};
  }
  header["frames"] = FlightPathFramesJson(options, session.plan, path, models);
  return manifest;
}

// Copies the inputs a flight-path dataset keeps into it.
void CopyFlightPathInputs(const RenderJobOptions& options, bool with_boom, const FlightPathInputHashes& hashes) {
  CopyInput(options.output, options.rig, kRigName, hashes.rig);
  CopyInput(options.output, options.receiver_model, kReceiverModelName, hashes.receiver);
  CopyInput(options.output, options.flight_path, kFlightPathName, hashes.path);
  if (with_boom) {
    CopyInput(options.output, options.boom_model, kBoomModelName, hashes.boom);
    CopyInput(options.output, options.boom_tube_model, kBoomTubeModelName, hashes.boom_tube);
  }
}

// What every frame of a flight-path job is made of.
struct FlightPathFrames {
  const RenderJobOptions& options;
  const StereoRig& rig;
  const std::vector<FlightSample>& path;
  const FlightPathModelIndices& models;
  bool with_boom;
  const std::vector<double>& exposure_offsets;
  const std::vector<Eigen::Vector3d>& receiver_points;
  const std::string& settings;
};

// Frame i of the flight path: the scene over its exposure, the scene at its instant, its sidecar.
std::tuple<std::vector<std::vector<RenderItem>>, std::vector<RenderItem>, FrameSidecar> FlightPathPair(
    const FlightPathFrames& frames, size_t i) {
  const std::vector<FlightSample>& path = frames.path;
  const Eigen::Isometry3d tanker_from_receiver = IsometryFromPose(path[i].tanker_from_receiver);
  // The scene at instant k of the exposure: tanker, receiver (instant k), boom.
  FrameSidecar s;
  std::vector<RenderItem> boom_items;
  if (frames.with_boom) {
    s.boom = path[i].boom.value_or(BoomPose{});
    boom_items = {{frames.models.boom, TankerFromBoom(*s.boom), kBoomId},
                  {frames.models.boom_tube, TankerFromBoomTube(*s.boom), kBoomId}};
  }
  const auto scene_with = [&](const std::vector<RenderItem>& receiver_items) {
    std::vector<RenderItem> items = {{frames.models.tanker, Eigen::Isometry3d::Identity(), kTankerId}};
    items.insert(items.end(), receiver_items.begin(), receiver_items.end());
    items.insert(items.end(), boom_items.begin(), boom_items.end());
    return items;
  };
  std::vector<std::vector<RenderItem>> exposure;
  for (const auto& receiver_items :
       ReceiverOverExposure(frames.models.receiver, path, i, frames.exposure_offsets, frames.options.propeller_rpm))
    exposure.push_back(scene_with(receiver_items));
  const std::vector<RenderItem> items = scene_with(
      ReceiverItems(frames.models.receiver, tanker_from_receiver, frames.options.propeller_rpm, path[i].time_s));
  const StereoRig& rig = frames.rig;
  s.kind = "frame";
  s.settings_sha256 = frames.settings;
  s.index = i;
  s.time_s = path[i].time_s;
  s.tanker_from_target = path[i].tanker_from_receiver;
  s.range_m = (tanker_from_receiver.translation() - rig.left.tanker_from_camera.translation()).norm();
  s.region = RegionForRange(s.range_m);
  s.in_view_left = InViewFraction(frames.receiver_points, rig.left, tanker_from_receiver);
  s.in_view_right = InViewFraction(frames.receiver_points, rig.right, tanker_from_receiver);
  s.rig = rig;
  return std::make_tuple(exposure, items, s);
}

}  // namespace

void RenderJobOptions::Check() const {
  CheckMsaaLevel(msaa);
  if (!(anisotropy >= 1.0f && anisotropy <= 16.0f)) {
    throw Error("--anisotropy " + std::to_string(anisotropy) + ": expected 1 (trilinear) to 16");
  }
  background.Check();
  if (!background.enabled() && (background.tanker_roll_deg != 0.0 || background.tanker_pitch_deg != 0.0)) {
    throw Error("--tanker-roll/--tanker-pitch: the flat sky has no horizon; use --background sky, terrain or clouds");
  }
  if (!(propeller_rpm >= 0.0 && propeller_rpm <= 3000.0)) {
    throw Error("--propellers " + FormatFixed(propeller_rpm, 1) + ": expected 0 (none) to 3000 rpm");
  }
  if (!(shutter_ms >= 0.0 && shutter_ms <= 100.0)) {
    throw Error("--shutter-ms " + FormatFixed(shutter_ms, 3) + ": expected 0 (an instant) to 100 ms");
  }
  if (time_samples < 2 || time_samples > 64 || (time_samples & (time_samples - 1)) != 0) {
    throw Error("--time-samples " + std::to_string(time_samples) + ": expected a power of two from 2 to 64");
  }
}

RenderJobResult RenderFlightPathJob(const RenderJobOptions& options) {
  options.Check();
  const StereoRig rig = LoadRig(options.rig);
  const StereoCalibration ideal = IdealCalibrationOf(rig, options.rig);
  const std::vector<FlightSample> path = ReadFlightPath(options.flight_path);
  options.selection.CheckWithin(path.size(), options.flight_path.string());
  if (options.shutter_ms > 0.0) CheckTimesIncrease(path, options.flight_path.string());
  const FlightPathModels models = LoadFlightPathModels(options, path);
  CheckDatasetFolderWritable(options.output);
  Session session = OpenSession(options, rig, options.background);
  const FlightPathModelIndices indices = AddFlightPathModels(session, models);
  const std::vector<double> exposure_offsets = ExposureOffsets(options.shutter_ms, options.time_samples);
  const std::vector<Eigen::Vector3d> receiver_points = models.receiver.AllPositions();

  EnsureWritableDirectory(options.output);
  const FileLock writing = LockDatasetForWriting(options.output);
  const FlightPathManifest manifest = FlightPathManifestHeader(options, session, models, path);
  const std::string settings = OpenManifest(options.output, "frame", manifest.header, [&] {
    CopyFlightPathInputs(options, models.with_boom, manifest.hashes);
    WriteCalibration(options.output / kIdealCalibrationName, ideal);
  });

  const FlightPathFrames frames{options,         rig,     path, indices, models.with_boom, exposure_offsets,
                                receiver_points, settings};
  return RunPairs(options, session, path.size(), "frame", settings, "render x" + std::to_string(options.msaa),
                  [&](size_t i) { return FlightPathPair(frames, i); });
}

RenderJobResult RenderCalibrationJob(const RenderJobOptions& options) {
  options.Check();
  const StereoRig rig = LoadRig(options.rig);
  const StereoCalibration ideal = IdealCalibrationOf(rig, options.rig);
  const SceneModel board = LoadSceneModel(options.board_model);
  CalibPoseOptions pose_options;
  pose_options.far_distances_m = options.far_boards_m;
  pose_options.corner_boards = options.corner_boards;
  const std::vector<Pose> poses = CalibrationBoardPoses(rig, pose_options);
  options.selection.CheckWithin(poses.size(), "calibration board poses");
  CheckDatasetFolderWritable(options.output);
  Session session = OpenSession(options, rig, BackgroundOptions{});
  const int board_index = session.renderer->AddModel(board);
  const std::vector<Eigen::Vector3d> board_points = board.AllPositions();
  const BoardSpec spec;

  EnsureWritableDirectory(options.output);
  const FileLock writing = LockDatasetForWriting(options.output);
  const std::string rig_hash = Sha256File(options.rig);
  nlohmann::json header = CommonHeader(session, rig_hash);
  header["inputs"]["board_model"] = {{"source", options.board_model.filename().string()},
                                     {"sha256", Sha256File(options.board_model)}};
  header["calib"] = {
      {"count", poses.size()},
      {"far_distances_m", options.far_boards_m},
      {"msaa", MsaaJson(session.plan)},
      {"texture_anisotropy", options.anisotropy},
      {"board", {{"inner_corners", {spec.inner_corners_x, spec.inner_corners_y}}, {"square_m", spec.square_m}}}};
  if (options.corner_boards) header["calib"]["corner_boards"] = true;  // absent: the earlier pose sets, unchanged
  const std::string settings = OpenManifest(options.output, "calib", header, [&] {
    CopyInput(options.output, options.rig, kRigName, rig_hash);
    WriteCalibration(options.output / kIdealCalibrationName, ideal);
  });

  return RunPairs(options, session, poses.size(), "calib", settings, "calib x" + std::to_string(options.msaa),
                  [&](size_t i) {
                    const Eigen::Isometry3d tanker_from_board = IsometryFromPose(poses[i]);
                    std::vector<RenderItem> items = {{board_index, tanker_from_board, kBoardId}};
                    FrameSidecar s;
                    s.kind = "calib";
                    s.settings_sha256 = settings;
                    s.index = i;
                    s.tanker_from_target = poses[i];
                    s.range_m = (tanker_from_board.translation() - rig.left.tanker_from_camera.translation()).norm();
                    s.in_view_left = InViewFraction(board_points, rig.left, tanker_from_board);
                    s.in_view_right = InViewFraction(board_points, rig.right, tanker_from_board);
                    s.rig = rig;
                    s.board = spec;
                    return std::make_tuple(std::vector<std::vector<RenderItem>>{items}, items, s);
                  });
}

}  // namespace aar
