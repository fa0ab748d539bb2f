#include "aar/renderer/shading.h"

#include "aar/error.h"

namespace aar {

std::string ToString(Shading shading) { return shading == Shading::kPbr ? "pbr" : "matte"; }

Shading ParseShading(const std::string& text) {
  if (text == "matte") return Shading::kMatte;
  if (text == "pbr") return Shading::kPbr;
  throw Error("unknown shading '" + text + "' (expected matte or pbr)");
}

}  // namespace aar
