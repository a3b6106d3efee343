// Metrics: symmetry-aware pose errors (BOP-style) and quantiles, against hand-computed values.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "laserfit/core/error.hpp"
#include "laserfit/metrics/pose_error.hpp"
#include "laserfit/metrics/stats.hpp"

using namespace laserfit;
namespace m = laserfit::metrics;

namespace {
Pose rotated(const Pose& T, double deg, const Eigen::Vector3d& axis_object) {
  Pose R = T;
  R.linear() = T.rotation() * Eigen::AngleAxisd(deg * M_PI / 180, axis_object).toRotationMatrix();
  return R;
}
const std::vector<Eigen::Vector3f> kBox = {{-5, -2, 0},  {5, -2, 0},  {5, 2, 0},  {-5, 2, 0},
                                           {-5, -2, 10}, {5, -2, 10}, {5, 2, 10}, {-5, 2, 10}};
}  // namespace

TEST(Metrics, PlainErrorsWithoutSymmetry) {
  Pose gt = Pose::Identity();
  gt.translation() = Eigen::Vector3d(500, 10, 100);
  Pose est = rotated(gt, 0.3, Eigen::Vector3d::UnitX());
  est.translation() += Eigen::Vector3d(0.003, 0.004, 0);  // 5 um
  const auto e = m::pose_error(est, gt, m::Symmetry{}, kBox);
  EXPECT_NEAR(e.t_mm, 0.005, 1e-12);
  EXPECT_NEAR(e.r_deg, 0.3, 1e-9);
  // MSSD: the farthest corner moves by the translation plus 0.3 deg about x at radius
  // sqrt(2^2+10^2).
  EXPECT_GT(e.mssd_mm, 0.005);
  EXPECT_LT(e.mssd_mm, 0.005 + std::hypot(2.0, 10.0) * 0.3 * M_PI / 180 + 1e-9);
}

TEST(Metrics, DiscreteSymmetryForgivesTheTwin) {
  const Pose gt = Pose::Identity();
  const m::Symmetry s = m::parse_symmetry("discrete 2 z");
  const auto flipped = m::pose_error(rotated(gt, 180.2, Eigen::Vector3d::UnitZ()), gt, s, kBox);
  EXPECT_NEAR(flipped.r_deg, 0.2, 1e-9);  // 180.2 deg = the twin + 0.2 deg
  const auto none =
      m::pose_error(rotated(gt, 180.2, Eigen::Vector3d::UnitZ()), gt, m::Symmetry{}, kBox);
  EXPECT_NEAR(none.r_deg, 179.8, 1e-9);
}

TEST(Metrics, ContinuousSymmetryIgnoresTheSpinOnly) {
  const Pose gt = Pose::Identity();
  const m::Symmetry s = m::parse_symmetry("continuous z");
  Pose est = rotated(gt, 73, Eigen::Vector3d::UnitZ());  // free spin
  est = rotated(est, 0.4, Eigen::Vector3d::UnitX());     // plus a real tilt of the axis
  const auto e = m::pose_error(est, gt, s);
  EXPECT_NEAR(e.r_deg, 0.4, 1e-9);
}

TEST(Metrics, SymmetryTextIsChecked) {
  EXPECT_EQ(m::parse_symmetry("continuous x").kind, m::Symmetry::Kind::Continuous);
  EXPECT_EQ(m::parse_symmetry("discrete 4 y").order, 4);
  EXPECT_THROW(m::parse_symmetry("discrete 1 z"), Error);
  EXPECT_THROW(m::parse_symmetry("spherical"), Error);
  EXPECT_THROW(m::parse_symmetry("continuous q"), Error);
  EXPECT_THROW(m::parse_symmetry("none extra"), Error);
}

TEST(Metrics, Quantiles) {
  EXPECT_DOUBLE_EQ(m::median({3, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(m::quantile({0, 10}, 0.95), 9.5);
  EXPECT_TRUE(std::isnan(m::median({})));
}
