#pragma once
// Walking a glTF 2.0 scene graph (tinygltf) with node transforms expressed in
// body axes (docs/frames.md); shared by the renderer's and the analyzer's
// model loaders.

#include <tiny_gltf.h>

#include <Eigen/Core>
#include <functional>
#include <string>

namespace aar {

/// Calls visit(mesh, body_from_node) for every node that has a mesh, depth
/// first, in the default scene (scene 0 when none is marked; every root node
/// when the file has no scenes). body_from_node = body_from_gltf * the node's
/// world matrix (its `matrix`, or T * R * S, composed down the hierarchy).
/// Throws aar::Error prefixed by `where` on a bad or cyclic hierarchy.
void ForEachMeshNode(const tinygltf::Model& model, const std::string& where,
                     const std::function<void(const tinygltf::Mesh&, const Eigen::Matrix4d&)>& visit);

}  // namespace aar
