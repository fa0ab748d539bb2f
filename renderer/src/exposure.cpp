#include "aar/renderer/exposure.h"

#include "aar/dataset.h"
#include "aar/propeller.h"

namespace aar {

std::vector<double> ExposureOffsets(double shutter_ms, int time_samples) {
  if (shutter_ms == 0.0) return {0.0};
  std::vector<double> offsets;
  for (int k = 0; k < time_samples; ++k)
    offsets.push_back(1e-3 * shutter_ms * ((k + 0.5) / static_cast<double>(time_samples) - 0.5));
  return offsets;
}

std::vector<RenderItem> ReceiverItems(const ReceiverModels& models, const Eigen::Isometry3d& tanker_from_receiver,
                                      double propeller_rpm, double time_s) {
  std::vector<RenderItem> items = {{models.airframe, tanker_from_receiver, models.object_id}};
  if (models.propeller >= 0) {
    for (int i = 0; i < static_cast<int>(kPropellerHubsInReceiver.size()); ++i) {
      items.push_back(
          {models.propeller, tanker_from_receiver * ReceiverFromPropeller(i, propeller_rpm, time_s), models.object_id});
    }
  }
  for (const auto& [model, light] : models.lights) {
    if (!light.OnAt(time_s)) continue;
    items.push_back({model, tanker_from_receiver * Eigen::Translation3d(light.position_in_receiver),
                     static_cast<float>(kReceiverLightsMaskId)});
  }
  return items;
}

std::vector<std::vector<RenderItem>> ReceiverOverExposure(const ReceiverModels& models,
                                                          const std::vector<FlightSample>& path, size_t index,
                                                          const std::vector<double>& offsets_s, double propeller_rpm) {
  std::vector<std::vector<RenderItem>> instants;
  for (double offset : offsets_s) {
    const double t = path[index].time_s + offset;
    // The sample itself exactly (an instant exposure renders what it always did).
    const Eigen::Isometry3d pose =
        offset == 0.0 ? IsometryFromPose(path[index].tanker_from_receiver) : TankerFromReceiverAt(path, t);
    instants.push_back(ReceiverItems(models, pose, propeller_rpm, t));
  }
  return instants;
}

nlohmann::json ExposureJson(double shutter_ms, int time_samples) {
  return {{"shutter_ms", shutter_ms},
          {"time_samples", time_samples},
          {"instants", "sample time + shutter * ((k + 0.5) / time_samples - 0.5), k = 0 .. time_samples - 1"},
          {"moving",
           "the receiver (between the path's samples: position linear, attitude slerp) and its propellers; "
           "the tanker and the boom are held"},
          {"truth", "depth, ids and the sidecar's pose are the sample time's (mid-exposure)"}};
}

nlohmann::json PropellersJson(double rpm) {
  nlohmann::json hubs = nlohmann::json::array(), phases = nlohmann::json::array();
  for (size_t i = 0; i < kPropellerHubsInReceiver.size(); ++i) {
    const Eigen::Vector3d& h = kPropellerHubsInReceiver[i];
    hubs.push_back({h.x(), h.y(), h.z()});
    phases.push_back(kPropellerPhaseDeg[i]);
  }
  return {{"rpm", rpm},
          {"blades", kPropellerBlades},
          {"diameter_m", kPropellerDiameterM},
          {"hubs_in_receiver_m", hubs},
          {"phase_deg", phases},
          {"receiver_from_propeller", "Translation(hub) * Rx(phase + 360 * rpm / 60 * time_s)"},
          {"mask_id", "the receiver's"}};
}

}  // namespace aar
