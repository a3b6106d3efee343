// Scanner profiles and flange poses (`laserfit assemble`): CSV rows of numbers in either layout,
// the same bytes as a binary profile file, and as a pose list.
#include "fuzz_util.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/profiles.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace laserfit;
  const std::string csv = fuzz::input_file("profiles.csv", data, size);
  const std::string bin = fuzz::input_file("profiles.bin", data, size);
  io::ProfileFileSettings s;
  s.layout = size % 2 ? io::ProfileLayout::blocks : io::ProfileLayout::interleaved;
  s.zero_is_invalid = size % 3 == 0;
  try {
    io::read_profiles(csv, s);
  } catch (const Error&) {
  }
  s.width = 1 + int(size % 5),
  s.scalar = size % 2 ? io::ProfileScalar::f32 : io::ProfileScalar::f64;
  try {
    io::read_profiles(bin, s);
  } catch (const Error&) {
  }
  try {
    io::read_pose_list(csv, Unit::Metre);
  } catch (const Error&) {
  }
  return 0;
}
