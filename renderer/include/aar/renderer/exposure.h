#pragma once
// What moves during a frame's exposure (issue 9, items 4 and 5;
// docs/rendering.md, "Motion blur and propellers"): the instants the
// exposure is sampled at, the receiver's render items at an instant (the
// airframe on the flight path, its propellers turning), and the manifest's
// record of both.

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <vector>

#include "aar/flight_path.h"
#include "aar/renderer/receiver_lights.h"
#include "aar/renderer/scene_renderer.h"

namespace aar {

/// The instants of an exposure, as offsets from the sample's time [s]:
/// shutter * ((k + 0.5) / n - 0.5) for k = 0 .. n - 1, the midpoints of n
/// equal slices of the exposure centred on the sample (box shutter). A
/// shutter of 0 is one instant, the sample's time.
std::vector<double> ExposureOffsets(double shutter_ms, int time_samples);

/// The receiver's models uploaded to the renderer: the airframe and, with
/// propellers, one propeller drawn at every hub (-1: none).
struct ReceiverModels {
  int airframe = -1;
  int propeller = -1;
  float object_id = 0.0f;
  /// With --receiver-lights: each light's sphere model and the light.
  std::vector<std::pair<int, ReceiverLight>> lights;
};

/// The receiver's items at `time_s` with the airframe at `tanker_from_receiver`:
/// the airframe, and each propeller at its hub turned to its angle at
/// `time_s` (propeller.h), all with the receiver's object id; and the
/// lights on at `time_s`, with theirs (kReceiverLightsMaskId).
std::vector<RenderItem> ReceiverItems(const ReceiverModels& models, const Eigen::Isometry3d& tanker_from_receiver,
                                      double propeller_rpm, double time_s);

/// The receiver's items at each instant of sample `index`'s exposure: the
/// airframe moved along `path` (TankerFromReceiverAt; at an offset of 0 the
/// sample's own pose) and its propellers turned to the instant.
std::vector<std::vector<RenderItem>> ReceiverOverExposure(const ReceiverModels& models,
                                                          const std::vector<FlightSample>& path, size_t index,
                                                          const std::vector<double>& offsets_s, double propeller_rpm);

/// frames.exposure of the manifest (with a shutter).
nlohmann::json ExposureJson(double shutter_ms, int time_samples);
/// frames.propellers of the manifest (with propellers).
nlohmann::json PropellersJson(double rpm);

}  // namespace aar
