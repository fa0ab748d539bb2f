// The tanker model: KC-46 class (Boeing 767-2C), plain grey, no boom, with a
// small fairing for the stereo cameras. See docs/scenes.md.
#pragma once

#include "glb_writer.h"

namespace aar::scenes {

/// Clearance of the tanker around the stereo rig of scenes/rig.json.
struct RigClearance {
  double fuselage_bottom_at_rig_m = 0;  ///< fuselage underside z at the rig station (x = -20)
  double lowest_near_rig_m = 0;         ///< lowest tanker z within 3 m (x) and 1.5 m (y) of the cameras
  std::size_t vertices_in_view = 0;     ///< tanker vertices inside either camera's view pyramid
};

/// Builds the KC-46: nodes fuselage, wing, stabilizer, fin, engine_left,
/// engine_right, pylon_left, pylon_right, camera_fairing; one grey material.
/// Origin = tanker frame origin (fuselage centre line, mid length).
/// Throws if any geometry lies inside the cameras' view or below the rig's limits.
SceneModel BuildKc46(RigClearance* clearance);

}  // namespace aar::scenes
