#pragma once
#include <map>
#include <string>

#include "laserfit/core/mesh.hpp"

namespace laserfit::io {

// Writes binary PLY (.ply) or binary STL (.stl), chosen by extension, atomically. PLY carries
// `comments` in its header (provenance); STL has room only for an 80-byte title.
void write_mesh(const std::string& path, const TriMesh& mesh,
                const std::map<std::string, std::string>& comments = {});

}  // namespace laserfit::io
