#pragma once
// The models of a flight-path job (stereo_render_job.h): loaded once, made
// thermal for an LWIR rig, added to a render session's renderer.

#include <optional>
#include <vector>

#include "aar/flight_path.h"
#include "aar/renderer/exposure.h"
#include "aar/renderer/receiver_lights.h"
#include "aar/renderer/render_session.h"
#include "aar/renderer/scene_model.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/thermal_scene.h"

namespace aar {

/// The models of a flight-path job: the receiver, the tanker, the boom and
/// its tube (with_boom) and the propeller (with_propellers).
struct FlightPathModels {
  SceneModel receiver, tanker;
  bool with_boom = false, with_propellers = false;
  std::optional<SceneModel> boom, boom_tube, propeller;
  std::vector<ReceiverLight> lights;  // with --receiver-lights
};

/// Loads the receiver, the tanker, the boom (the path's columns or options.boom) and the propeller.
FlightPathModels LoadFlightPathModels(const RenderJobOptions& options, const std::vector<FlightSample>& path);

/// A thermal rig's models: every surface unlit at its band radiance (thermal_scene.h).
void ApplyThermal(FlightPathModels& models, const ThermalScene& thermal);

/// The flight-path models' indices on the renderer; -1 for the boom's without it.
struct FlightPathModelIndices {
  ReceiverModels receiver;
  int tanker = -1, boom = -1, boom_tube = -1;
};

/// Adds the models to the session's renderer: receiver, tanker, boom, boom
/// tube, propeller, the lights' spheres (at the background's render scale).
FlightPathModelIndices AddFlightPathModels(RenderSession& session, const FlightPathModels& models,
                                           const BackgroundOptions& background);

}  // namespace aar
