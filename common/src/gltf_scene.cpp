#include "aar/gltf_scene.h"

#include <Eigen/Geometry>
#include <vector>

#include "aar/error.h"
#include "aar/pose.h"

namespace aar {
namespace {

// gltf_from_node of one node: its matrix, or T * R * S (glTF 2.0 section 5.25).
Eigen::Matrix4d LocalTransform(const tinygltf::Node& node, const std::string& where) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m(r, c) = node.matrix[static_cast<size_t>(c * 4 + r)];  // column-major
    }
    return m;
  }
  if (!node.matrix.empty()) throw Error(where + ": node matrix must have 16 elements");
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) {
    t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (node.rotation.size() == 4) {  // glTF quaternion order is x, y, z, w
    const Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    if (q.norm() < 1e-12) throw Error(where + ": node rotation is a zero quaternion");
    t.rotate(q.normalized());
  }
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

void VisitNode(const tinygltf::Model& model, int node_index, const Eigen::Matrix4d& body_from_parent,
               const std::string& where, int depth,
               const std::function<void(const tinygltf::Mesh&, const Eigen::Matrix4d&)>& visit) {
  if (node_index < 0 || static_cast<size_t>(node_index) >= model.nodes.size()) {
    throw Error(where + ": node " + std::to_string(node_index) + " does not exist");
  }
  if (depth > 256) throw Error(where + ": node hierarchy is cyclic or deeper than 256");
  const tinygltf::Node& node = model.nodes[static_cast<size_t>(node_index)];
  const Eigen::Matrix4d body_from_node = body_from_parent * LocalTransform(node, where);
  if (node.mesh >= 0) {
    if (static_cast<size_t>(node.mesh) >= model.meshes.size()) {
      throw Error(where + ": mesh " + std::to_string(node.mesh) + " does not exist");
    }
    visit(model.meshes[static_cast<size_t>(node.mesh)], body_from_node);
  }
  for (const int child : node.children) VisitNode(model, child, body_from_node, where, depth + 1, visit);
}

}  // namespace

void ForEachMeshNode(const tinygltf::Model& model, const std::string& where,
                     const std::function<void(const tinygltf::Mesh&, const Eigen::Matrix4d&)>& visit) {
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (static_cast<size_t>(scene) >= model.scenes.size()) throw Error(where + ": default scene does not exist");
    roots = model.scenes[static_cast<size_t>(scene)].nodes;
  } else {  // no scenes: every node that is nobody's child
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes) {
      for (const int child : node.children) {
        if (child >= 0 && static_cast<size_t>(child) < is_child.size()) is_child[static_cast<size_t>(child)] = true;
      }
    }
    for (size_t i = 0; i < model.nodes.size(); ++i) {
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
    }
  }
  Eigen::Matrix4d body_from_gltf = Eigen::Matrix4d::Identity();
  body_from_gltf.topLeftCorner<3, 3>() = BodyFromGltf();
  for (const int root : roots) VisitNode(model, root, body_from_gltf, where, 0, visit);
}

}  // namespace aar
