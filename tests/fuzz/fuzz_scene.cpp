// Scene files (`laserfit scan`, benchmarks, cells): strict YAML, meshes relative to the file.
#include "fuzz_util.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/scan/scanner.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  laserfit::fuzz::repository_fixture();
  const std::string path = laserfit::fuzz::input_file("datasets/scenes/input.yaml", data, size);
  try {
    const auto scene = laserfit::scan::load_scene(path);
    if (scene.objects.empty()) __builtin_trap();  // a loaded scene has something to scan
  } catch (const laserfit::Error&) {
  }
  return 0;
}
