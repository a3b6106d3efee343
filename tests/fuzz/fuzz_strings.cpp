// The strings a user types: poses ("x y z qw qx qy qz" or 16 numbers), units, symmetries,
// shards ("i/N") and controller strategies. The first byte picks the parser.
#include "fuzz_util.hpp"
#include "laserfit/bench/trial.hpp"
#include "laserfit/controller/controller.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/core/units.hpp"
#include "laserfit/metrics/pose_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 5) {
      case 0: {
        const laserfit::Pose T = laserfit::parse_pose(text, "--pose");
        // A parsed pose is a finite rigid transform.
        const Eigen::Matrix3d R = T.linear();
        if (!T.matrix().allFinite() ||
            (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6)
          __builtin_trap();
        break;
      }
      case 1:
        laserfit::unit_to_mm(laserfit::parse_unit(text));
        break;
      case 2:
        laserfit::metrics::parse_symmetry(text);
        break;
      case 3: {
        const auto s = laserfit::bench::parse_shard(text);
        if (s.n < 1 || s.i < 0 || s.i >= s.n) __builtin_trap();
        break;
      }
      default:
        laserfit::parse_enum<laserfit::controller::Strategy>(text);
        break;
    }
  } catch (const laserfit::Error&) {
  }
  return 0;
}
