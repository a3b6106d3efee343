#pragma once
#include <map>
#include <string>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/cloud.hpp"

namespace laserfit::io {

// Binary PCD (.pcd, v0.7, readable by PCL) or binary PLY (.ply), by extension, atomically.
// Fields x y z [normal_x normal_y normal_z]; organized clouds keep WIDTH x HEIGHT with NaN for
// invalid points. cloud.metadata goes into header comments ("# laserfit.<key> <value>" in PCD,
// "comment laserfit.<key> <value>" in PLY), so every file says where it came from.
void write_cloud(const std::string& path, const PointCloud& cloud);
// The same into an open AtomicFile (the caller commits), for commands that write several files
// and commit them together.
void write_cloud(AtomicFile& file, const PointCloud& cloud);

// Reads PCD (ascii / binary / binary_compressed) or PLY through PCL, plus our header metadata.
// Throws laserfit::Error naming the file for missing, empty, truncated or malformed input.
PointCloud read_cloud(const std::string& path);

// Only the "laserfit.*" header comments of a cloud or mesh file.
std::map<std::string, std::string> read_header_metadata(const std::string& path);

}  // namespace laserfit::io
