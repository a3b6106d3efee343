// The scan / reference cloud readers (PCD and PLY, as `register` and the benchmark read them).
// The first byte picks the format; the rest is the file.
#include "fuzz_util.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string name = data[0] & 1 ? "cloud.ply" : "cloud.pcd";
  const std::string path = laserfit::fuzz::input_file(name, data + 1, size - 1);
  try {
    const laserfit::PointCloud c = laserfit::io::read_cloud(path);
    if (c.points.empty()) __builtin_trap();  // the reader promises at least one point
  } catch (const laserfit::Error&) {
  }
  return 0;
}
