// A dataset's manifest.json (`bench --dataset`, `bench generate --verify`): the files it lists
// are checked for size and CRC-32; it must not be able to point outside its dataset.
#include "fuzz_util.hpp"
#include "laserfit/bench/dataset.hpp"
#include "laserfit/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto dir = laserfit::fuzz::work_dir() / "dataset";
  std::filesystem::create_directories(dir / "scans");
  static const bool scan = [&] {  // one listed file to find: "scans/0.pcd", 4 bytes "scan"
    laserfit::fuzz::input_file("dataset/scans/0.pcd", reinterpret_cast<const uint8_t*>("scan"), 4);
    return true;
  }();
  (void)scan;
  laserfit::fuzz::input_file("dataset/manifest.json", data, size);
  try {
    laserfit::bench::verify_dataset(dir.string());
  } catch (const laserfit::Error&) {
  }
  return 0;
}
