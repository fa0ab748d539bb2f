#include "aar/renderer/flight_path_models.h"

#include "aar/renderer/daylight.h"

namespace aar {

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
  if (options.receiver_lights) models.lights = ReceiverLightsOf(models.receiver);
  return models;
}

void ApplyThermal(FlightPathModels& models, const ThermalScene& thermal) {
  models.receiver = thermal.Apply(models.receiver);
  models.tanker = thermal.Apply(models.tanker);
  for (std::optional<SceneModel>* model : {&models.boom, &models.boom_tube, &models.propeller}) {
    if (*model) **model = thermal.Apply(**model);
  }
}

FlightPathModelIndices AddFlightPathModels(RenderSession& session, const FlightPathModels& models,
                                           const BackgroundOptions& background) {
  FlightPathModelIndices indices;
  indices.receiver.airframe = session.renderer->AddModel(models.receiver);
  indices.receiver.object_id = kReceiverObjectId;
  indices.tanker = session.renderer->AddModel(models.tanker);
  indices.boom = models.with_boom ? session.renderer->AddModel(*models.boom) : -1;
  indices.boom_tube = models.with_boom ? session.renderer->AddModel(*models.boom_tube) : -1;
  if (models.with_propellers) indices.receiver.propeller = session.renderer->AddModel(*models.propeller);
  for (const ReceiverLight& light : models.lights) {
    indices.receiver.lights.emplace_back(session.renderer->AddModel(LightSphereModel(light, RenderScale(background))),
                                         light);
  }
  return indices;
}

}  // namespace aar
