#pragma once
// Plain images that pass between the renderer's stages: the scene's linear
// colour and its ground truth (depth, object ids). No device types: the
// CPU-only image and sensor modules (aar_renderer_image) take these.

#include <cstdint>
#include <vector>

namespace aar {

/// Linear RGB floats, row-major, 3 per pixel.
struct LinearImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;
};

/// One camera's ground truth, row-major, one value per pixel.
struct GroundTruthImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth_m;      ///< along the optical axis, 0 where no surface
  std::vector<uint8_t> object_id;  ///< the object id of the item seen there (RenderItem), 0 for background
};

}  // namespace aar
