#pragma once
// Point clouds as PLY files (Turk 1994): binary writer, ascii/binary reader.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace aar {

/// Writes points as a binary_little_endian PLY (element vertex, float x y z),
/// readable by Open3D, PCL and CloudCompare; atomic (aar::WriteFileAtomic).
/// `comments` become "comment" header lines (no newlines allowed).
void WritePly(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<std::string>& comments = {});

/// Reads the x, y, z properties of the vertex element of a PLY file: ascii,
/// binary_little_endian or binary_big_endian, scalar properties of any PLY
/// type, other properties skipped, elements after `vertex` ignored. Throws
/// aar::Error naming the file and the reason otherwise.
std::vector<Eigen::Vector3d> ReadPly(const std::filesystem::path& path);

}  // namespace aar
