// The C-12's propeller (issue 9, item 5; docs/scenes.md, "Propellers"): four
// twisted blades in the propeller frame of common/include/aar/propeller.h
// (origin at the hub, x the rotation axis, blade 0 along +z). The spinner is
// part of c12.glb; the renderer places and turns one copy per engine.
#pragma once

#include "c12_airframe.h"
#include "glb_writer.h"

namespace aar::scenes {

/// Nodes blades, tips; materials propeller_black, propeller_tip.
SceneModel BuildC12Propeller();

/// Throws aar::Error when propeller.h's hub positions are not 0.30 m aft of
/// the airframe's spinner tips on the nacelle axes (to 0.5 mm).
void CheckPropellerHubs(const C12Airframe& airframe);

}  // namespace aar::scenes
