// The KC-46 class flying boom, in the boom frame of common/include/aar/boom.h
// (origin at the hinge, the boom along -x): the fixed part (hinge fairing,
// outer tube, ruddevators) and the telescoping tube with its nozzle, which
// the renderer moves aft by the extension. See docs/scenes.md, "Boom".
#pragma once

#include "glb_writer.h"

namespace aar::scenes {

/// Nodes fairing, outer_tube, ruddevators; one material kc46_boom_grey.
SceneModel BuildKc46Boom();

/// Nodes inner_tube, nozzle (retracted position); materials kc46_boom_grey, boom_nozzle.
SceneModel BuildKc46BoomTube();

}  // namespace aar::scenes
