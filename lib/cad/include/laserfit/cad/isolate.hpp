#pragma once
// The CAD readers' side of laserfit/core/isolate.hpp: what a reader child returns (RawMesh) and
// its encoding, which the parent decodes as untrusted bytes.
#include <functional>
#include <string>

#include "laserfit/core/isolate.hpp"
#include "laserfit/core/mesh.hpp"

namespace laserfit::cad {

// What a reader returns before unit resolution and repair (see import.hpp).
struct RawMesh {
  TriMesh mesh;
  std::vector<std::string> parts;
  double declared_to_mm = 0.0;  // > 0 when the file declares its unit (scale to mm)
  std::string declared_unit;    // as written in the file, e.g. "MM", "meter=0.001", "m (glTF)"
  std::vector<std::string> warnings;
};

// run_isolated for a mesh reader: `read` runs in the child, its RawMesh comes back decoded.
RawMesh read_isolated(const std::string& path, const std::string& reader,
                      const IsolationLimits& limits, const std::function<RawMesh()>& read);

// The child-to-parent message, exposed so that it can be tested (and fuzzed) on its own.
// decode throws laserfit::Error naming `path`.
std::string encode_raw_mesh(const RawMesh& raw);
RawMesh decode_raw_mesh(const std::string& bytes, const std::string& path);

}  // namespace laserfit::cad
