// What the parent does with a reader child's answer, whatever it holds: decode it (a lying or
// broken child must not crash the parent), then check and repair the mesh with CGAL (degenerate,
// duplicated, non-manifold, inside-out or non-finite geometry straight from a hostile file).
#include "laserfit/cad/isolate.hpp"
#include "laserfit/cad/repair.hpp"
#include "laserfit/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    laserfit::cad::RawMesh raw = laserfit::cad::decode_raw_mesh(bytes, "child");
    laserfit::cad::RepairSettings s;
    s.fill_holes = size % 2 == 0;
    laserfit::cad::check_and_repair(raw.mesh, s, "child");
    // What decodes must encode back to the same bytes.
    if (laserfit::cad::encode_raw_mesh(laserfit::cad::decode_raw_mesh(bytes, "child")) != bytes)
      __builtin_trap();
  } catch (const laserfit::Error&) {
  }
  return 0;
}
