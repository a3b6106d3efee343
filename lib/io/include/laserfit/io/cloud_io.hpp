#pragma once
#include <map>
#include <string>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/cloud.hpp"
#include "laserfit/core/units.hpp"

namespace laserfit::io {

// Binary PCD (.pcd, v0.7, readable by PCL) or binary PLY (.ply), by extension, atomically.
// Fields x y z [normal_x normal_y normal_z]; organized clouds keep WIDTH x HEIGHT with NaN for
// invalid points. cloud.metadata goes into header comments ("# laserfit.<key> <value>" in PCD,
// "comment laserfit.<key> <value>" in PLY), so every file says where it came from.
void write_cloud(const std::string& path, const PointCloud& cloud);
// The same into an open AtomicFile (the caller commits), for commands that write several files
// and commit them together.
void write_cloud(AtomicFile& file, const PointCloud& cloud);

// Reads PCD (ascii / binary / binary_compressed) or PLY (ascii / binary) through PCL, plus our
// header metadata. Fields x y z (and normals) may be float or double, as Open3D writes them; an
// organized PLY keeps its grid (obj_info num_cols / num_rows). The sensor origin comes from the
// laserfit.viewpoint comment, else from a PCD VIEWPOINT / PLY camera that is not the origin.
// Returns millimetres: a file that states its unit (laserfit.unit) is read in it, any other in
// `unstated` (Unit::Auto: refused, the caller must say). Throws laserfit::Error naming the file
// for missing, empty, truncated or malformed input.
PointCloud read_cloud(const std::string& path, Unit unstated = Unit::Millimetre);

// Only the "laserfit.*" header comments of a cloud or mesh file.
std::map<std::string, std::string> read_header_metadata(const std::string& path);

}  // namespace laserfit::io
