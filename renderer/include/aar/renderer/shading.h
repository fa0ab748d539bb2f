#pragma once
// How the renderer lights surfaces (docs/rendering.md, "Physically based
// shading"): the shader scene.frag is compiled once per kind.

#include <string>

namespace aar {

enum class Shading {
  kMatte,  ///< Lambertian: the sun and a hemispherical sky on the base colour (the default)
  kPbr,    ///< glTF metallic-roughness: the same diffuse light plus the sun's and the sky's specular reflection
};

/// "matte" or "pbr".
std::string ToString(Shading shading);
/// "matte" or "pbr"; aar::Error naming the text otherwise.
Shading ParseShading(const std::string& text);

}  // namespace aar
