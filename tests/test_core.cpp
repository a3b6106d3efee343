// Core types: poses, units, atomic files, seeded RNG blocks.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/core/units.hpp"
#include "test_util.hpp"

using namespace laserfit;

TEST(Pose, ParsesTranslationQuaternionAndMatrix) {
  // Tolerance: 1e-12 (exact arithmetic on simple values).
  const Pose a = parse_pose("1 2 3 0.7071067811865476 0 0 0.7071067811865476");
  EXPECT_NEAR((a * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1, 3, 3)).norm(), 0, 1e-12);
  const Pose b = parse_pose("[0,-1,0,1; 1,0,0,2; 0,0,1,3; 0,0,0,1]");
  EXPECT_NEAR((a.matrix() - b.matrix()).norm(), 0, 1e-12);
  const auto tq = pose_to_tq(a);
  EXPECT_GE(tq[3], 0.0);
  EXPECT_NEAR((parse_pose(pose_to_string(a)).matrix() - a.matrix()).norm(), 0, 1e-12);
}

TEST(Pose, RejectsMalformedPoses) {
  EXPECT_THROW(parse_pose("1 2 3"), Error);
  EXPECT_THROW(parse_pose("1 2 3 2 0 0 0"), Error);    // not a unit quaternion
  EXPECT_THROW(parse_pose("1 2 nan 1 0 0 0"), Error);  // NaN
  EXPECT_THROW(parse_pose("1 2 3 1 0 0 zero"), Error);
  EXPECT_THROW(parse_pose("2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"), Error);  // scaled, not rigid
}

TEST(Pose, RotationAngleIsGeodesic) {
  const Eigen::Quaterniond a(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond b(Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(rotation_angle(a, b), 0.5, 1e-12);
  Eigen::Quaterniond minus_a = a;
  minus_a.coeffs() *= -1;  // the same rotation
  EXPECT_NEAR(rotation_angle(a, minus_a), 0.0, 1e-7);
}

TEST(Pose, LookAtPointsZAtTarget) {
  const Pose T = look_at({0, 0, 100}, {0, 0, 0});
  EXPECT_NEAR((T.linear().col(2) - Eigen::Vector3d(0, 0, -1)).norm(), 0, 1e-12);
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
}

TEST(Units, ParseScaleAndGuess) {
  EXPECT_EQ(unit_to_mm(parse_unit("m")), 1000.0);
  EXPECT_EQ(unit_to_mm(parse_unit("in")), 25.4);
  EXPECT_THROW(parse_unit("furlong"), Error);
  EXPECT_EQ(guess_unit_from_extent(0.03), Unit::Metre);  // a 30 mm part written in metres
  EXPECT_EQ(guess_unit_from_extent(70.0), Unit::Millimetre);
}

TEST(AtomicFile, NoPartialFileWithoutCommit) {
  test::TempDir dir;
  const std::string path = dir / "out.bin";
  {
    AtomicFile f(path);
    f.stream() << "half";
  }  // destroyed without commit, as when an exception unwinds
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path));
  write_file_atomic(path, "whole");
  EXPECT_EQ(test::read_bytes(path), "whole");
  EXPECT_THROW(AtomicFile(dir / "missing_dir/out.bin"), Error);
}

// A path the OS refuses (here a 300-character name, over NAME_MAX) is one laserfit::Error whose
// message shows at most 160 characters of it plus the reason, never a std::filesystem_error.
TEST(InputFile, HostilePathsAreOneClippedError) {
  test::TempDir dir;
  const std::string too_long = dir / (std::string(300, 'a') + ".ply");
  try {
    require_input_file(too_long);
    FAIL() << "no error for a name over NAME_MAX";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("File name too long"), std::string::npos) << what;
    EXPECT_LT(what.size(), 160u + 80u) << what;
  }
  EXPECT_THROW(AtomicFile{too_long}, Error);
  EXPECT_THROW(require_input_file(dir / "missing.ply"), Error);
  EXPECT_THROW(require_input_file(dir.path.string()), Error);  // a folder
  write_file_atomic(dir / "empty.ply", "");
  EXPECT_THROW(require_input_file(dir / "empty.ply"), Error);
  EXPECT_NO_THROW(require_input_file(dir / "empty.ply", "listed", EmptyFile::allowed));
  EXPECT_EQ(shown_path("short"), "short");
}

TEST(Rng, BlocksAreIndependentOfOrder) {
  auto a = block_rng(7, 1, 3), b = block_rng(7, 1, 3), c = block_rng(7, 1, 4);
  EXPECT_EQ(a(), b());
  EXPECT_NE(block_rng(7, 1, 3)(), c());
  const double u = uniform01(a);
  EXPECT_GE(u, 0.0);
  EXPECT_LT(u, 1.0);
}

// laserfit's generator must be std::mt19937_64 bit for bit: every seeded scan, trial and campaign
// record depends on its stream. Tolerance: exact, over 3 x 312 twists for seeds at the extremes.
TEST(Rng, MersenneTwisterIsStdMt19937_64BitForBit) {
  for (uint64_t seed : {uint64_t(0), uint64_t(1), uint64_t(5489), ~uint64_t(0), mix_seed(42)}) {
    std::mt19937_64 expected(seed);
    Mt19937_64 g(seed);
    for (int i = 0; i < 3 * 312 * 312; ++i)
      ASSERT_EQ(g(), expected()) << "seed " << seed << " #" << i;
  }
  EXPECT_EQ(Mt19937_64()(), std::mt19937_64()());  // the same default seed
}
