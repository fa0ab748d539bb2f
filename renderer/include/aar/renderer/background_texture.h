#pragma once
// Procedural, tileable textures of the background (docs/rendering.md,
// "Backgrounds"), generated on the CPU from a seed with integer hashing only
// and plain float arithmetic (the same seed gives the same bytes), with a mip chain
// (scene_model.h's BuildMips). The shader repeats them over the ground plane
// or the cloud deck at BackgroundOptions::ground_texel_m / cloud_texel_m.

#include <cstdint>

#include "aar/renderer/scene_model.h"

namespace aar {

inline constexpr int kTerrainTextureSize = 2048;  ///< texels per side of the terrain tile
inline constexpr int kCloudTextureSize = 1024;    ///< texels per side of the cloud tile

/// Terrain, `size` x `size` texels (a power of two, >= 256), periodic: a road
/// grid (1-texel roads on 256-texel blocks, some left out, and a 2-texel
/// winding highway), fields (each block cut into rows and parcels of
/// 24-128 texels, one crop colour each, with plough rows and hedges), forest
/// patches, lakes and a river. At 8 m per texel: 2.05 km blocks, 8 m roads,
/// fields of 190 m to 1 km, a 16.4 km tile.
TextureMips TerrainTexture(uint32_t seed, int size = kTerrainTextureSize);

/// Cloud-deck tops, `size` x `size` texels (power of two, >= 256), periodic:
/// billowy fractal value noise in bright white to blue-grey.
TextureMips CloudTexture(uint32_t seed, int size = kCloudTextureSize);

}  // namespace aar
