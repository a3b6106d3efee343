// Cell files (`laserfit-controller sim` / `correct`): strict YAML with a scene, arms, grasp,
// calibration errors and the insertion geometry.
#include "fuzz_util.hpp"
#include "laserfit/cell/cell.hpp"
#include "laserfit/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  laserfit::fuzz::repository_fixture();
  const std::string path = laserfit::fuzz::input_file("cells/input.yaml", data, size);
  try {
    laserfit::cell::load_cell(path);
  } catch (const laserfit::Error&) {
  }
  return 0;
}
