// The mesh readers as `laserfit import` calls them: import_cad, whose parser runs in an isolated
// child (crashes and runaways there are answered as errors), then the decoding of the child's
// answer, unit resolution and the CGAL check and repair in this process. The first byte picks
// the format (STL, PLY, OBJ, OFF); the rest is the file.
#include "fuzz_util.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExt[] = {"stl", "ply", "obj", "off"};
  const std::string path =
      laserfit::fuzz::input_file(std::string("mesh.") + kExt[data[0] % 4], data + 1, size - 1);
  laserfit::cad::ImportSettings s;
  s.reader.timeout_s = 10;
  s.reader.memory_mib = 256;  // an input is <= 64 KiB: beyond this it is a runaway, killed sooner
  try {
    const auto r = laserfit::cad::import_cad(path, s);
    if (r.mesh.faces.empty()) __builtin_trap();  // import promises a non-empty mesh
  } catch (const laserfit::Error&) {
  }
  return 0;
}
