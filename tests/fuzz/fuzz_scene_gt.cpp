// BOP ground truth (scene_gt.json, scene_prior.json) of a recorded benchmark scene: a lab's file,
// or one another tool wrote; only laserfit::Error may come back.
#include "fuzz_util.hpp"
#include "laserfit/bench/recorded.hpp"
#include "laserfit/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = laserfit::fuzz::input_file("scene_gt.json", data, size);
  try {
    laserfit::bench::read_scene_gt(path);
  } catch (const laserfit::Error&) {
  }
  return 0;
}
