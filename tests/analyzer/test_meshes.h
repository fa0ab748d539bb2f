#pragma once
// Synthetic meshes shared by the analyzer tests.

#include <Eigen/Core>

#include "aar/analyzer/mesh.h"

namespace aar::test {

/// Appends a closed axis-aligned box (12 triangles, outward winding).
inline void AddBox(TriangleMesh& mesh, const Eigen::Vector3d& centre, const Eigen::Vector3d& half) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.push_back(centre + Eigen::Vector3d((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                                                     (i & 4) ? half.z() : -half.z()));
  }
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : faces) {
    mesh.triangles.emplace_back(base + q[0], base + q[1], base + q[2]);
    mesh.triangles.emplace_back(base + q[0], base + q[2], base + q[3]);
  }
}

}  // namespace aar::test
