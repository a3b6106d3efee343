#pragma once
// A cloud as bytes, for the isolated reader child's answer (laserfit/core/isolate.hpp): size,
// grid, then points, normals, labels and the sensor origin (0 or 3 values), each preceded by its
// count. The parent decodes it as
// untrusted input: counts are checked against the bytes and the grid before anything is
// allocated from them.
#include <string>

#include "laserfit/core/cloud.hpp"

namespace laserfit::io {

std::string encode_cloud(const PointCloud& cloud);  // metadata not included
PointCloud decode_cloud(const std::string& bytes, const std::string& path);  // throws Error

}  // namespace laserfit::io
