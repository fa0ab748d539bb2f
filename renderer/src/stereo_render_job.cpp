#include "aar/renderer/stereo_render_job.h"

#include <unistd.h>

#include <algorithm>
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
#include "aar/renderer/daylight.h"
#include "aar/renderer/exposure.h"
#include "aar/renderer/flight_path_models.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/pair_writer.h"
#include "aar/renderer/projection.h"
#include "aar/renderer/render_session.h"
#include "aar/renderer/rolling_shutter.h"
#include "aar/renderer/shadow_map.h"
#include "aar/stereo_calibration.h"
#include "aar/text.h"

namespace aar {
namespace {

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

// Shared loop: renders the selected pairs not yet complete, then finalizes.
template <typename MakePair>
RenderJobResult RunPairs(const RenderJobOptions& options, RenderSession& session, size_t count, const std::string& kind,
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
      auto [bands, sidecar] = make_pair(index);
      writer.Push(RenderPair(session, bands, dir, std::move(sidecar), depth_sides, result.times));
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

// Hashes of the inputs a flight-path dataset keeps a copy of; the boom's empty without it.
struct FlightPathInputHashes {
  std::string rig, receiver, path, boom, boom_tube;
};

struct FlightPathManifest {
  nlohmann::json header;
  FlightPathInputHashes hashes;
};

// frames of the manifest: how every frame of the flight path is rendered.
nlohmann::json FlightPathFramesJson(const RenderJobOptions& options, const RenderSession& session,
                                    const std::vector<FlightSample>& path, const FlightPathModels& models) {
  const MsaaPlan& plan = session.plan;
  nlohmann::json frames = {{"count", path.size()},
                           {"msaa", MsaaJson(plan)},
                           {"depth", options.depth || options.depth_right},
                           {"depth_right", options.depth_right},
                           {"texture_anisotropy", options.anisotropy}};
  // Absent for the flat sky, so datasets made before backgrounds existed still match.
  if (options.background.enabled()) frames["background"] = BackgroundJson(options.background);
  // Absent for the sun every dataset had before it could be set, likewise.
  if (options.background.sun) frames["sun"] = SunJson(options.background);
  // Absent without the boom, so datasets without it keep their bytes.
  if (models.with_boom) frames["boom"] = BoomJson(path.front().boom.has_value());
  // Absent for an instant exposure and without propellers, likewise.
  if (options.shutter_ms > 0.0) frames["exposure"] = ExposureJson(options.shutter_ms, options.time_samples);
  // Absent for a global shutter, likewise.
  if (session.left_readout) frames["rolling_shutter"] = RollingShutterJson(session.readout_ms, options.readout_bands);
  if (models.with_propellers) frames["propellers"] = PropellersJson(options.propeller_rpm);
  if (!models.lights.empty()) frames["receiver_lights"] = ReceiverLightsJson(models.lights);
  // Absent for matte shading, likewise.
  if (options.shading != Shading::kMatte) frames["shading"] = ToString(options.shading);
  if (options.shadows) {
    const Intrinsics& map = session.RenderCamera("left").intrinsics;
    frames["shadows"] = ShadowsJson(map.width_px, map.height_px);
  }
  if (session.floodlight) {
    frames["floodlight"] = session.floodlight->Json();
    frames["floodlight"]["illuminance_lx_at_aim"] = options.floodlight->illuminance_lx;
  }
  // Absent by day at the rig's exposure, likewise.
  if (session.thermal) frames["thermal"] = session.thermal->Json();
  if (session.auto_exposure) {
    frames["auto_exposure"] = AutoExposureJson(*options.auto_exposure, options.exposure_ev,
                                               RenderScale(options.background), *session.auto_exposure);
  } else if (session.exposure) {
    frames["camera_exposure"] = {
        {"exposure_ev", options.exposure_ev},
        {"render_scale", RenderScale(options.background)},
        {"factor", session.exposure->factor()},
        {"model", "radiance x 2^exposure_ev / render_scale before the lens and the sensor (camera_exposure.h)"}};
  }
  return frames;
}

// The manifest header of a flight-path job; hashes its inputs, writes nothing.
FlightPathManifest FlightPathManifestHeader(const RenderJobOptions& options, const RenderSession& session,
                                            const FlightPathModels& models, const std::vector<FlightSample>& path) {
  FlightPathManifest manifest;
  FlightPathInputHashes& hashes = manifest.hashes;
  hashes.rig = Sha256File(options.rig);
  hashes.receiver = Sha256File(options.receiver_model);
  hashes.path = Sha256File(options.flight_path);
  nlohmann::json& header = manifest.header;
  header = SessionManifestHeader(session, hashes.rig);
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
  header["frames"] = FlightPathFramesJson(options, session, path, models);
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
  const std::vector<double>& band_offsets;  // a rolling shutter's bands (rolling_shutter.h); {0}: a global shutter
  const std::vector<Eigen::Vector3d>& receiver_points;
  const std::string& settings;
};

// Frame i of the flight path: each readout band's scene over its exposure and at its instant.
std::vector<BandScene> FlightPathBands(const FlightPathFrames& frames, size_t i) {
  const std::vector<FlightSample>& path = frames.path;
  const Eigen::Isometry3d tanker_from_receiver = IsometryFromPose(path[i].tanker_from_receiver);
  // The scene at instant k of the exposure: tanker, receiver (instant k), boom.
  std::vector<RenderItem> boom_items;
  if (frames.with_boom) {
    const BoomPose boom = path[i].boom.value_or(BoomPose{});
    boom_items = {{frames.models.boom, TankerFromBoom(boom), kBoomId},
                  {frames.models.boom_tube, TankerFromBoomTube(boom), kBoomId}};
  }
  const auto scene_with = [&](const std::vector<RenderItem>& receiver_items) {
    std::vector<RenderItem> items = {{frames.models.tanker, Eigen::Isometry3d::Identity(), kTankerId}};
    items.insert(items.end(), receiver_items.begin(), receiver_items.end());
    items.insert(items.end(), boom_items.begin(), boom_items.end());
    return items;
  };
  std::vector<BandScene> bands;
  for (double band_offset : frames.band_offsets) {
    BandScene band;
    std::vector<double> offsets = frames.exposure_offsets;
    for (double& o : offsets) o += band_offset;
    for (const auto& receiver_items :
         ReceiverOverExposure(frames.models.receiver, path, i, offsets, frames.options.propeller_rpm))
      band.exposure.push_back(scene_with(receiver_items));
    band.instant = scene_with(
        band_offset == 0.0
            ? ReceiverItems(frames.models.receiver, tanker_from_receiver, frames.options.propeller_rpm, path[i].time_s)
            : ReceiverOverExposure(frames.models.receiver, path, i, {band_offset}, frames.options.propeller_rpm)[0]);
    bands.push_back(std::move(band));
  }
  return bands;
}

// Frame i's bands and its sidecar.
std::tuple<std::vector<BandScene>, FrameSidecar> FlightPathPair(const FlightPathFrames& frames, size_t i) {
  const std::vector<FlightSample>& path = frames.path;
  const Eigen::Isometry3d tanker_from_receiver = IsometryFromPose(path[i].tanker_from_receiver);
  FrameSidecar s;
  if (frames.with_boom) s.boom = path[i].boom.value_or(BoomPose{});
  std::vector<BandScene> bands = FlightPathBands(frames, i);
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
  return std::make_tuple(std::move(bands), s);
}

// Auto-exposure: every frame of the path metered in order by the left
// camera at its instant, small and pinhole, with one sample per pixel, so
// that the schedule is the path's whatever the selection (shards and resumed
// runs agree); the session's exposure then follows it frame by frame.
void MeterAutoExposure(const RenderJobOptions& options, const FlightPathModels& models, const SessionLighting& lighting,
                       const std::vector<FlightSample>& path, RenderSession& session) {
  const AutoExposureOptions& ae = *options.auto_exposure;
  StereoRig small = session.rig;
  small.sensor.reset();
  for (Camera* camera : {&small.left, &small.right}) {
    Intrinsics& k = camera->intrinsics;
    const int width = (k.width_px + ae.meter_downscale - 1) / ae.meter_downscale;
    const int height = (k.height_px + ae.meter_downscale - 1) / ae.meter_downscale;
    const double sx = static_cast<double>(width) / k.width_px, sy = static_cast<double>(height) / k.height_px;
    k = Intrinsics{
        width,         height, k.fx_px * sx, k.fy_px * sy, (k.cx_px + 0.5) * sx - 0.5, (k.cy_px + 0.5) * sy - 0.5,
        BrownConrady{}};
  }
  RenderJobOptions meter_options = options;
  meter_options.msaa = 1;
  SessionLighting meter_lighting = lighting;
  meter_lighting.exposure_ev = 0.0;
  RenderSession meter = OpenRenderSession(meter_options, small, options.background, meter_lighting);
  const FlightPathModelIndices indices = AddFlightPathModels(meter, models, options.background);
  const std::vector<double> instant = {0.0};
  const std::vector<Eigen::Vector3d> no_points;
  const std::string no_settings;
  const FlightPathFrames frames{meter_options, small,   path,      indices,    models.with_boom,
                                instant,       instant, no_points, no_settings};
  std::vector<double> times_s;
  for (const FlightSample& sample : path) times_s.push_back(sample.time_s);
  const double full_scale =
      session.rig.sensor ? std::min(1.0, session.rig.sensor->full_well_e / session.rig.sensor->exposure_e) : 1.0;
  std::optional<Progress> progress;
  if (options.progress) progress.emplace("auto-exposure: meter", path.size());
  const double render_scale = RenderScale(options.background);
  session.auto_exposure = RunAutoExposure(times_s, options.exposure_ev, render_scale, full_scale, ae, [&](size_t i) {
    const LinearImage image = meter.renderer->RenderColor(meter.RenderCamera("left"), small.near_m,
                                                          FlightPathBands(frames, i).front().instant, meter.plan);
    if (progress) progress->Advance();
    return image;
  });
  if (progress) progress->Finish();
  session.exposure.emplace(session.auto_exposure->ev, render_scale);
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
  if (!(exposure_ev >= -10.0 && exposure_ev <= 24.0)) {
    throw Error("--exposure-ev " + FormatFixed(exposure_ev, 3) + ": expected -10 to 24 (powers of two)");
  }
  if (floodlight) floodlight->Check();
  if (!(shutter_ms >= 0.0 && shutter_ms <= 100.0)) {
    throw Error("--shutter-ms " + FormatFixed(shutter_ms, 3) + ": expected 0 (an instant) to 100 ms");
  }
  if (time_samples < 2 || time_samples > 64 || (time_samples & (time_samples - 1)) != 0) {
    throw Error("--time-samples " + std::to_string(time_samples) + ": expected a power of two from 2 to 64");
  }
  if (auto_exposure) auto_exposure->Check();
  if (readout_bands < 1 || readout_bands > kMaxReadoutBands) {
    throw Error("--readout-bands " + std::to_string(readout_bands) + ": expected 1 to " +
                std::to_string(kMaxReadoutBands));
  }
}

// A thermal rig renders emission over the flat sky: no light to shade, expose or cast shadows.
void CheckThermalJob(const RenderJobOptions& options, const StereoRig& rig) {
  const std::string where = options.rig.string() + " declares an LWIR camera (lwir): ";
  if (!rig.lwir) {
    if (options.thermal) {
      throw Error("--airspeed, --sky-temperature and --nacelle-excess: only with a rig that declares lwir");
    }
    return;
  }
  if (options.background.kind != BackgroundKind::kFlat) {
    throw Error(where + "the thermal camera renders over the flat sky only (--background flat)");
  }
  if (options.shading != Shading::kMatte || options.shadows || options.floodlight || options.receiver_lights ||
      options.exposure_ev != 0.0 || options.auto_exposure) {
    throw Error(where +
                "--shading, --shadows, --floodlight, --receiver-lights, --exposure-ev and --auto-exposure "
                "are the visible camera's; the thermal scene is emission (docs/rendering.md, \"Thermal "
                "camera\")");
  }
}

RenderJobResult RenderFlightPathJob(const RenderJobOptions& options) {
  options.Check();
  const StereoRig rig = LoadRig(options.rig);
  CheckThermalJob(options, rig);
  const StereoCalibration ideal = IdealCalibrationOf(rig, options.rig);
  const std::vector<FlightSample> path = ReadFlightPath(options.flight_path);
  options.selection.CheckWithin(path.size(), options.flight_path.string());
  const double readout_ms = rig.sensor ? rig.sensor->readout_ms : 0.0;
  if (options.shutter_ms > 0.0 || readout_ms > 0.0) CheckTimesIncrease(path, options.flight_path.string());
  FlightPathModels models = LoadFlightPathModels(options, path);
  CheckDatasetFolderWritable(options.output);
  SessionLighting lighting{options.shading, options.shadows, options.exposure_ev, std::nullopt};
  if (options.floodlight) {
    std::vector<Eigen::Vector3d> positions;
    for (const FlightSample& sample : path) positions.push_back(sample.tanker_from_receiver.translation_m);
    lighting.floodlight = MakeFloodlight(*options.floodlight, rig, positions);
  }
  RenderSession session = OpenRenderSession(options, rig, options.background, lighting);
  if (session.thermal) ApplyThermal(models, *session.thermal);
  const FlightPathModelIndices indices = AddFlightPathModels(session, models, options.background);
  if (options.auto_exposure) MeterAutoExposure(options, models, lighting, path, session);
  const std::vector<double> exposure_offsets = ExposureOffsets(options.shutter_ms, options.time_samples);
  const std::vector<double> band_offsets =
      readout_ms > 0.0 ? ReadoutBandOffsets(readout_ms, options.readout_bands) : std::vector<double>{0.0};
  const std::vector<Eigen::Vector3d> receiver_points = models.receiver.AllPositions();

  EnsureWritableDirectory(options.output);
  const FileLock writing = LockDatasetForWriting(options.output);
  const FlightPathManifest manifest = FlightPathManifestHeader(options, session, models, path);
  const std::string settings = OpenManifest(options.output, "frame", manifest.header, [&] {
    CopyFlightPathInputs(options, models.with_boom, manifest.hashes);
    WriteCalibration(options.output / kIdealCalibrationName, ideal);
  });

  const FlightPathFrames frames{
      options, rig, path, indices, models.with_boom, exposure_offsets, band_offsets, receiver_points, settings};
  return RunPairs(options, session, path.size(), "frame", settings, "render x" + std::to_string(options.msaa),
                  [&](size_t i) { return FlightPathPair(frames, i); });
}

RenderJobResult RenderCalibrationJob(const RenderJobOptions& options) {
  options.Check();
  const StereoRig rig = LoadRig(options.rig);
  if (options.thermal && !rig.lwir) throw Error("--board-temperature: only with a rig that declares lwir");
  const StereoCalibration ideal = IdealCalibrationOf(rig, options.rig);
  const SceneModel board = LoadSceneModel(options.board_model);
  CalibPoseOptions pose_options;
  pose_options.far_distances_m = options.far_boards_m;
  pose_options.corner_boards = options.corner_boards;
  const std::vector<Pose> poses = CalibrationBoardPoses(rig, pose_options);
  options.selection.CheckWithin(poses.size(), "calibration board poses");
  CheckDatasetFolderWritable(options.output);
  RenderSession session = OpenRenderSession(options, rig, BackgroundOptions{}, SessionLighting{});
  const int board_index = session.renderer->AddModel(session.thermal ? session.thermal->ApplyBoard(board) : board);
  const std::vector<Eigen::Vector3d> board_points = board.AllPositions();
  const BoardSpec spec;

  EnsureWritableDirectory(options.output);
  const FileLock writing = LockDatasetForWriting(options.output);
  const std::string rig_hash = Sha256File(options.rig);
  nlohmann::json header = SessionManifestHeader(session, rig_hash);
  header["inputs"]["board_model"] = {{"source", options.board_model.filename().string()},
                                     {"sha256", Sha256File(options.board_model)}};
  header["calib"] = {
      {"count", poses.size()},
      {"far_distances_m", options.far_boards_m},
      {"msaa", MsaaJson(session.plan)},
      {"texture_anisotropy", options.anisotropy},
      {"board", {{"inner_corners", {spec.inner_corners_x, spec.inner_corners_y}}, {"square_m", spec.square_m}}}};
  if (options.corner_boards) header["calib"]["corner_boards"] = true;  // absent: the earlier pose sets, unchanged
  if (session.thermal) header["calib"]["thermal"] = session.thermal->BoardJson();
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
                    // The boards do not move: one band, whatever the shutter.
                    return std::make_tuple(std::vector<BandScene>{{{items}, items}}, s);
                  });
}

}  // namespace aar
