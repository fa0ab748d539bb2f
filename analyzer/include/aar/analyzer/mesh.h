#pragma once
// The receiver's triangle mesh in the receiver body frame (docs/frames.md),
// read from the dataset's receiver.glb. Reference models (reference_model.h)
// are sampled on it and the shelled model's visibility test rasterizes it.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "aar/opened_dataset.h"

namespace aar {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;   ///< receiver body frame (x forward, y left, z up) [m]
  std::vector<Eigen::Vector3i> triangles;  ///< indices into `vertices`, glTF (counter-clockwise) winding
};

/// Reads every triangle of a .glb or .gltf file: all nodes of the default
/// scene (scene 0 when none is marked default; every root node when the file
/// has no scenes), node matrices or TRS applied down the hierarchy, primitives
/// of mode TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN, indexed or not. The
/// result is in the body frame: point_in_body = BodyFromGltf() * point_in_gltf.
/// Vertices are not merged across primitives. Images are not decoded.
/// Throws aar::Error naming the file when it is missing, cannot be parsed,
/// has malformed accessors, or holds no triangle.
TriangleMesh LoadReceiverMesh(const std::filesystem::path& path);
/// The same for the render input `name` of `dataset` (kReceiverModelName,
/// kBoomModelName, kBoomTubeModelName), as OpenedDataset::Open read and
/// checked it; throws aar::Error naming the file when the dataset has none.
TriangleMesh LoadInputMesh(const OpenedDataset& dataset, const std::string& name);

/// Area of one triangle [m^2].
double TriangleArea(const TriangleMesh& mesh, size_t triangle);

/// Total surface area [m^2].
double SurfaceArea(const TriangleMesh& mesh);

}  // namespace aar
