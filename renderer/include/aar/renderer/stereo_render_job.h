#pragma once
// The two rendering jobs behind `aar-render render` and `aar-render calib`:
// validate every input, then render stereo pairs into a dataset folder,
// skipping frames that are already complete and verified (resume), and
// finalize the manifest when the dataset is complete.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aar/data_path.h"
#include "aar/frame_selection.h"
#include "aar/renderer/auto_exposure.h"
#include "aar/renderer/background.h"
#include "aar/renderer/floodlight.h"
#include "aar/renderer/shading.h"
#include "aar/renderer/thermal_scene.h"

namespace aar {

struct RenderJobOptions {
  std::filesystem::path output;                                            ///< dataset folder (created)
  std::filesystem::path rig = DataFile("scenes/rig.json");                 ///< camera rig
  std::filesystem::path receiver_model = DataFile("scenes/c12.glb");       ///< receiver glTF
  std::filesystem::path tanker_model = DataFile("scenes/kc46.glb");        ///< tanker glTF
  std::filesystem::path board_model = DataFile("scenes/calib_board.glb");  ///< calibration board glTF (calib job)
  /// The boom (render job, docs/scenes.md "Boom"): its fixed part and its
  /// telescoping tube, in the boom frame of boom.h.
  std::filesystem::path boom_model = DataFile("scenes/kc46_boom.glb");
  std::filesystem::path boom_tube_model = DataFile("scenes/kc46_boom_tube.glb");
  /// Put the boom in the scene. A flight path with the boom columns always
  /// has it; this adds it to a 7-column path, at BoomPose's defaults (stowed).
  bool boom = false;
  /// The receiver's propeller (docs/scenes.md, "Propellers"), placed and
  /// turned at each hub of propeller.h (render job, with propeller_rpm > 0).
  std::filesystem::path propeller_model = DataFile("scenes/c12_propeller.glb");
  /// Engine speed [rpm]: 0 leaves the propellers out (the thesis's receiver);
  /// otherwise both turn at this speed, 0 to 3000.
  double propeller_rpm = 0.0;
  /// The receiver's position, anti-collision and strobe lights
  /// (receiver_lights.h; render job).
  bool receiver_lights = false;
  /// Exposure time of each frame [ms], centred on the sample's time: 0 is an
  /// instant (no motion blur); otherwise the receiver and its propellers
  /// move during the exposure (docs/rendering.md, "Motion blur"), 0 to 100.
  double shutter_ms = 0.0;
  /// Instants the exposure is sampled at (a power of two, 2 to 64), with shutter_ms > 0.
  int time_samples = 16;
  /// A rolling shutter's frame (the rig's sensor.readout_ms > 0) is rendered
  /// in this many bands of rows, each at its own instant (rolling_shutter.h):
  /// a row's instant is off by at most readout / (2 bands); 1 to 1024.
  int readout_bands = 32;
  /// How the aircraft are lit (render job; the calibration boards stay
  /// matte): kMatte, or kPbr for the models' glTF metallic-roughness
  /// materials with the sun's and the sky's specular reflection.
  Shading shading = Shading::kMatte;
  /// The sun's shadows on the receiver (render job; docs/rendering.md,
  /// "Shadows"): what every model (tanker, boom, receiver, propellers) casts
  /// on the receiver and its propellers.
  bool shadows = false;
  /// The camera's exposure relative to the one the rig is stated for [EV,
  /// powers of two] (render job; camera_exposure.h), -10 to 24: 0 by day;
  /// at night, what a camera gains from a longer shutter and a wider
  /// aperture (the calibration boards are shot by day, at 0).
  double exposure_ev = 0.0;
  /// Auto-exposure (auto_exposure.h; render job): the camera meters each
  /// frame and sets the next one's exposure, from exposure_ev at frame 0.
  std::optional<AutoExposureOptions> auto_exposure;
  /// A thermal rig's scene (thermal_scene.h; render job): airspeed, sky,
  /// nacelles; only with a rig that declares lwir (its defaults then when empty).
  std::optional<ThermalSceneOptions> thermal;
  /// The tanker's floodlight on the receiver (floodlight.h; render job).
  std::optional<FloodlightOptions> floodlight;
  std::filesystem::path flight_path = DataFile("flightpaths/conops.csv");  ///< flight path (render job)
  int msaa = 16;                                                           ///< 1, 4, 8, 16 or 32 samples per pixel
  float anisotropy = 1.0f;   ///< texture anisotropic filtering (1 = trilinear)
  bool depth = false;        ///< also write left-camera depth EXR, object ids and receiver silhouette (render job)
  bool depth_right = false;  ///< the same for the right camera (implies `depth`)
  /// Calib job: the twelve board tilts again at each of these distances [m].
  /// Default 30 and 45 m (36 pairs): boards at one distance leave the focal
  /// lengths and the baseline's length confounded (docs/analysis.md); {} =
  /// the thesis's twelve near boards.
  std::vector<double> far_boards_m = {30.0, 45.0};
  bool corner_boards = false;    ///< calib job: eight more boards towards the image corners and edges
  BackgroundOptions background;  ///< render job: behind the receiver (calibration boards keep the flat sky)
  FrameSelection selection;      ///< frames (or calib pairs) to render
  std::string device;            ///< Vulkan device name filter ("" = lavapipe first)
  bool progress = true;          ///< progress line on stderr

  /// Throws aar::Error naming the option (its command-line flag) when a value
  /// is out of range (MSAA level, anisotropy outside [1, 16] or NaN, the
  /// background's values, a tanker attitude with the flat sky, the
  /// propellers' speed, the shutter and its time samples); the jobs
  /// call it before reading any input. Input defaults come from data_path.h.
  void Check() const;
};

/// Accumulated wall time per stage over the pairs rendered [ms]. Encoding
/// and writing run on the pair writer's thread (pair_writer.h), beside the
/// rendering of the next pair: the stages overlap, and wall_ms, not their
/// sum, is the run's time.
struct RenderStageTimes {
  double render_ms = 0.0;    ///< GPU passes (all MSAA passes of both views, truth passes)
  double readback_ms = 0.0;  ///< copies to host memory, half-to-float, averaging, the truth's lens resampling
  double encode_ms = 0.0;    ///< writer thread: lens resampling and sensor model (rigs with them), sRGB conversion, PNG
                             ///< (and EXR) encoding
  double write_ms = 0.0;     ///< writer thread: hashing and atomic writes of images and sidecars
  double wait_ms = 0.0;      ///< the renderer waiting for the writer (queue full; the last pairs)
  double wall_ms = 0.0;      ///< the whole loop: resume checks, rendering, and the last pair written
};

struct RenderJobResult {
  size_t selected = 0;    ///< pairs in the selection
  size_t rendered = 0;    ///< pairs rendered by this run
  size_t skipped = 0;     ///< pairs already complete and verified
  bool complete = false;  ///< the whole dataset is complete (manifest finalized)
  RenderStageTimes times;
  std::string msaa_method;  ///< "native" or "composed"
  std::string device;       ///< Vulkan device name
};

RenderJobResult RenderFlightPathJob(const RenderJobOptions& options);
RenderJobResult RenderCalibrationJob(const RenderJobOptions& options);

}  // namespace aar
