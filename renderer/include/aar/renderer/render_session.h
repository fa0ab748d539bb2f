#pragma once
// What a render job opens once and shares between its pairs: the Vulkan
// device and scene renderer, the MSAA plan, the lens resamplers of a
// distorted rig (docs/rendering.md) and the rig's sensor model; one stereo
// pair rendered in it; and its description in the dataset's manifest.

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "aar/dataset.h"
#include "aar/renderer/auto_exposure.h"
#include "aar/renderer/background.h"
#include "aar/renderer/camera_exposure.h"
#include "aar/renderer/lens_distortion.h"
#include "aar/renderer/lens_flare.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/pair_writer.h"
#include "aar/renderer/rolling_shutter.h"
#include "aar/renderer/scene_renderer.h"
#include "aar/renderer/sensor_model.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/sun_glare.h"
#include "aar/renderer/thermal_sensor.h"
#include "aar/renderer/vulkan_context.h"
#include "aar/rig.h"

namespace aar {

/// The receiver's object id in the truth passes (docs/dataset-format.md, "Images").
inline constexpr float kReceiverObjectId = 1.0f;

struct RenderSession {
  StereoRig rig;
  std::unique_ptr<VulkanContext> context;
  std::unique_ptr<SceneRenderer> renderer;
  MsaaPlan plan;
  // With lens distortion (docs/rendering.md): both cameras are rendered as
  // pinhole cameras on one grown image and resampled; empty for a pinhole rig.
  std::optional<LensResampler> left_lens, right_lens;
  // The sun's veiling glare on each pinhole render, where the rig's sensor declares it.
  std::optional<SunGlare> left_glare, right_glare;
  // Lens flare's ghosts of the sun on each pinhole render, where the rig's sensor declares them.
  std::optional<LensFlare> left_flare, right_flare;
  // The camera's exposure and the night's render scale divided out; empty
  // where their factor is 1 (by day at the rig's exposure).
  std::optional<CameraExposure> exposure;
  // With auto-exposure: every frame's exposure and metered level (the exposure's factors per frame).
  std::optional<AutoExposureSchedule> auto_exposure;
  std::optional<Floodlight> floodlight;  // the tanker's floodlight, where it shines
  // A thermal rig's scene radiometry and detector (the rig's lwir); null otherwise.
  std::shared_ptr<const ThermalScene> thermal;
  std::shared_ptr<const ThermalSensor> thermal_sensor;
  // The rig's sensor, its fixed patterns drawn once for the whole run; null without one.
  std::shared_ptr<const SensorModel> sensor;
  // A rolling shutter (the sensor's readout_ms > 0): the readout time and
  // the band of every rendered pixel per camera; empty for a global shutter.
  double readout_ms = 0.0;
  std::optional<ReadoutBands> left_readout, right_readout;

  const Camera& RigCamera(const std::string& side) const { return side == "left" ? rig.left : rig.right; }
  const std::optional<LensResampler>& Lens(const std::string& side) const {
    return side == "left" ? left_lens : right_lens;
  }
  const std::optional<ReadoutBands>& Readout(const std::string& side) const {
    return side == "left" ? left_readout : right_readout;
  }
  /// The effects a view's radiance passes through before its encoding, in
  /// order (view_effect.h): the sun's glare, the lens flare's ghosts, the camera's exposure, the
  /// lens's resampling, then the sensor. A new image effect is made in OpenRenderSession and listed here.
  std::vector<const ViewEffect*> ViewEffects(const std::string& side) const {
    std::vector<const ViewEffect*> effects;
    const std::optional<SunGlare>& glare = side == "left" ? left_glare : right_glare;
    if (glare) effects.push_back(&*glare);
    const std::optional<LensFlare>& flare = side == "left" ? left_flare : right_flare;
    if (flare) effects.push_back(&*flare);
    if (exposure) effects.push_back(&*exposure);
    if (Lens(side)) effects.push_back(&*Lens(side));
    if (sensor) effects.push_back(sensor.get());
    if (thermal_sensor) effects.push_back(thermal_sensor.get());
    return effects;
  }
  /// The camera the scene is rendered with: the rig's, or its pinhole stand-in.
  Camera RenderCamera(const std::string& side) const {
    Camera camera = RigCamera(side);
    if (Lens(side)) camera.intrinsics = Lens(side)->pinhole();
    return camera;
  }
};

/// How the aircraft are lit beyond the background's sun and sky, and how
/// the cameras expose the scene.
struct SessionLighting {
  Shading shading = Shading::kMatte;  ///< matte, or the models' glTF materials
  bool shadows = false;               ///< the sun's shadows on the receiver
  double exposure_ev = 0.0;           ///< the camera's exposure (camera_exposure.h)
  std::optional<Floodlight> floodlight;
};

/// Opens the device (options.device), plans MSAA (options.msaa), makes the
/// lens resamplers, the sensor model and the readout bands
/// (options.readout_bands) of `rig`, and the scene renderer at the size the
/// scene is rendered with, over `background`, lit and exposed as `lighting` says.
RenderSession OpenRenderSession(const RenderJobOptions& options, const StereoRig& rig,
                                const BackgroundOptions& background, const SessionLighting& lighting);

/// The scene of one readout band of a rolling shutter, or of the whole frame
/// (a global shutter, or what does not move): at each instant of its
/// exposure (one: no motion), and at its own instant, which the truth shows.
struct BandScene {
  std::vector<std::vector<RenderItem>> exposure;
  std::vector<RenderItem> instant;
};

/// Renders one stereo pair (and the truth of `depth_sides`) for the
/// PairWriter to encode and write: from one band, or from the session's
/// readout bands, each pixel from the band it is in (rolling_shutter.h;
/// aar::Error when their counts differ).
RenderedPair RenderPair(RenderSession& session, const std::vector<BandScene>& bands, const std::string& dir,
                        FrameSidecar sidecar, const std::vector<std::string>& depth_sides, RenderStageTimes& times);

/// The manifest's description of an MSAA plan (frames.msaa, calib.msaa).
nlohmann::json MsaaJson(const MsaaPlan& plan);

/// The manifest keys both jobs share (schema, renderer, device, image with
/// its lens and sensor, the rig's input); computes nothing, writes nothing.
nlohmann::json SessionManifestHeader(const RenderSession& session, const std::string& rig_hash);

}  // namespace aar
