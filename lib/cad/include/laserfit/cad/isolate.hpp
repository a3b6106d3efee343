#pragma once
// Third-party parsers (OpenCASCADE for STEP/IGES, assimp for the mesh formats) read untrusted
// files in ways laserfit cannot fix: a corrupt file can crash them, make them loop, or make them
// allocate without bound. They therefore run in a forked child process with a wall-clock and an
// address-space limit; the child hands the mesh back through an anonymous memory file, and
// whatever happens to it (signal, abort, exception, runaway) becomes one laserfit::Error naming
// the file, in the parent, which has written nothing.
#include <functional>
#include <string>

#include "laserfit/core/mesh.hpp"

namespace laserfit::cad {

struct IsolationLimits {
  bool isolate = true;       // false: parse in this process (debugging a reader only)
  double timeout_s = 60.0;   // wall-clock limit of one read (s); 0: none
  double memory_mib = 8192;  // address-space limit of the reader process (MiB); 0: none
};

// What a reader returns before unit resolution and repair (see import.hpp).
struct RawMesh {
  TriMesh mesh;
  std::vector<std::string> parts;
  double declared_to_mm = 0.0;  // > 0 when the file declares its unit (scale to mm)
  std::string declared_unit;    // as written in the file, e.g. "MM", "meter=0.001", "m (glTF)"
  std::vector<std::string> warnings;
};

// Runs `read` in a child process under `limits` and returns its mesh. `reader` names the parser
// in messages ("the STEP reader crashed (signal 11, Segmentation fault)"). Throws laserfit::Error
// naming `path` for a crash, a timeout, exhausted memory, or the reader's own error.
RawMesh read_isolated(const std::string& path, const std::string& reader,
                      const IsolationLimits& limits, const std::function<RawMesh()>& read);

// The child-to-parent message, exposed so that it can be tested (and fuzzed) on its own: the
// parent treats it as untrusted input. decode throws laserfit::Error naming `path`.
std::string encode_raw_mesh(const RawMesh& raw);
RawMesh decode_raw_mesh(const std::string& bytes, const std::string& path);

}  // namespace laserfit::cad
