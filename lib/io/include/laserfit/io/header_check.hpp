#pragma once
// PCL's PCD and PLY readers trust their headers: a field list that does not match its sizes, a
// point count beyond the data, or a claimed 10^12 points crash them or make them allocate
// without bound. So the header is parsed and checked here first, against the file's size, and
// anything implausible is refused before PCL (or assimp, for meshes) sees the file.
#include <cstddef>
#include <string>

namespace laserfit::io {

constexpr size_t kMaxCloudPoints = 200'000'000;  // a 2048-point scanner's 100 000 profiles, 2x

// Throws laserfit::Error naming `path` unless the header is well formed and the data it
// announces fits in the file. `ext` is ".pcd" or ".ply".
void check_cloud_header(const std::string& path, const std::string& ext);

// The same checks for the mesh formats whose headers announce counts (PLY; binary STL: 80-byte
// header, triangle count, 50 bytes a triangle; OFF: vertex and face counts, a line each), before
// a mesh parser is started: a claimed 10^9 triangles is refused here rather than attempted.
// `max_elements` bounds every count.
void check_mesh_header(const std::string& path, const std::string& ext, size_t max_elements);

}  // namespace laserfit::io
