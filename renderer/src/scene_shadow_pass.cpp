// The sun's shadow maps (docs/rendering.md, "Shadows"): per instant of an
// exposure, the sun camera framing the items of options().shadow_object_id
// renders the depth of every item, which scene.frag's AAR_SHADOWS variants
// compare against; a map is rendered again only when its instant's items
// moved (the two cameras of a pair share them).

#include <cstring>

#include "aar/renderer/scene_renderer.h"
#include "aar/renderer/sun_camera.h"

namespace aar {

void SceneRenderer::PrepareShadowMap(size_t slot, const std::vector<RenderItem>& items) {
  std::vector<double> key;
  for (const RenderItem& item : items) {
    key.push_back(item.model);
    key.push_back(item.object_id);
    key.insert(key.end(), item.tanker_from_object.matrix().data(), item.tanker_from_object.matrix().data() + 16);
  }
  if (slot < shadow_keys_.size() && shadow_keys_[slot] == key) return;
  Eigen::AlignedBox3d framed;
  for (const RenderItem& item : items) {
    if (item.object_id != options_.shadow_object_id) continue;
    const Eigen::AlignedBox3d& bounds = GeometryOf(item.model).bounds;
    if (bounds.isEmpty()) continue;
    for (int corner = 0; corner < 8; ++corner) {
      framed.extend(item.tanker_from_object * bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
    }
  }
  if (framed.isEmpty()) framed = Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const Camera sun =
      SunCamera(sun_direction_in_tanker_, framed.center(), 0.5 * framed.diagonal().norm(), width_, height_);
  shadows_->Upload(slot, TruthPass(sun, 0.5 * kSunCameraDistanceM, items, nullptr, false), sun);
  if (shadow_keys_.size() <= slot) shadow_keys_.resize(slot + 1);
  shadow_keys_[slot] = std::move(key);
}

}  // namespace aar
