// Tuned thresholds (`register --thresholds`, `bench --thresholds`, the controller): every value
// with its unit, ranges checked, unknown and missing keys refused.
#include "fuzz_util.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/registration/thresholds.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = laserfit::fuzz::input_file("thresholds.yaml", data, size);
  try {
    laserfit::registration::load_thresholds(path);
  } catch (const laserfit::Error&) {
  }
  return 0;
}
