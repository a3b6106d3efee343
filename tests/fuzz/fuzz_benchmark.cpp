// Benchmark files (`laserfit bench`, `tune`): strict YAML naming scenes, targets, conditions.
#include "fuzz_util.hpp"
#include "laserfit/bench/spec.hpp"
#include "laserfit/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  laserfit::fuzz::repository_fixture();
  const std::string path = laserfit::fuzz::input_file("benchmarks/input.yaml", data, size);
  try {
    laserfit::bench::load_benchmark(path);
  } catch (const laserfit::Error&) {
  }
  return 0;
}
