// Panda kinematics: the published zero pose, the Jacobian against finite differences, IK round
// trips, the null-space bias (IC1 vs IC2) and the configuration-dependent error of a perturbed arm.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "laserfit/core/rng.hpp"
#include "laserfit/robot/error_model.hpp"
#include "laserfit/robot/ik.hpp"

using namespace laserfit;
using robot::Joints;

namespace {

const robot::ArmModel kPanda = robot::ArmModel::panda();

Joints random_q(laserfit::Mt19937_64& g, double margin = 0.2) {
  Joints q;
  for (int j = 0; j < 7; ++j) {
    const double lo = kPanda.limits.q_min[j] + margin, hi = kPanda.limits.q_max[j] - margin;
    q[j] = lo + (hi - lo) * uniform01(g);
  }
  return q;
}

// A typical ready pose (the Panda's "ready" configuration) and its elbow-swapped sibling.
Joints ready() {
  Joints q;
  q << 0, -M_PI / 4, 0, -3 * M_PI / 4, 0, M_PI / 2, M_PI / 4;
  return q;
}

double pos_err(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
double rot_err(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace

// Tolerance: 1e-9 mm (exact arithmetic on the DH table).
TEST(Robot, ZeroPoseMatchesThePublishedFlangePosition) {
  const Pose T = kPanda.fk(Joints::Zero());
  EXPECT_NEAR(T.translation().x(), 88.0, 1e-9);
  EXPECT_NEAR(T.translation().y(), 0.0, 1e-9);
  EXPECT_NEAR(T.translation().z(), 926.0, 1e-9);
  EXPECT_NEAR(T.linear().col(2).z(), -1.0, 1e-12);  // flange z points down
}

// Tolerance: 1e-5 (central differences with h = 1e-6 rad; mm per rad and rad per rad).
TEST(Robot, JacobianMatchesFiniteDifferences) {
  laserfit::Mt19937_64 g(7);
  for (int k = 0; k < 20; ++k) {
    const Joints q = random_q(g);
    const robot::Jacobian J = kPanda.jacobian(q);
    for (int j = 0; j < 7; ++j) {
      Joints a = q, b = q;
      const double h = 1e-6;
      a[j] -= h, b[j] += h;
      const Pose Ta = kPanda.fk(a), Tb = kPanda.fk(b);
      const Eigen::Vector3d v = (Tb.translation() - Ta.translation()) / (2 * h);
      const Eigen::AngleAxisd w(Tb.linear() * Ta.linear().transpose());
      EXPECT_LT((v - J.block<3, 1>(0, j)).norm(), 1e-5 * std::max(1.0, v.norm()));
      EXPECT_LT((w.axis() * w.angle() / (2 * h) - J.block<3, 1>(3, j)).norm(), 1e-5);
    }
  }
}

// Tolerance: every solve converges to 1e-6 mm / 1e-8 rad from a start 0.3 rad away per joint.
TEST(Robot, IkRoundTrips) {
  laserfit::Mt19937_64 g(11);
  for (int k = 0; k < 50; ++k) {
    const Joints q = random_q(g, 0.4);
    Joints start = q;
    for (int j = 0; j < 7; ++j) start[j] += 0.3 * (2 * uniform01(g) - 1);
    const Pose target = kPanda.fk(q);
    const auto r = robot::solve_ik(kPanda, target, start);
    ASSERT_TRUE(r.converged) << "config " << k << ": " << r.error_mm << " mm";
    EXPECT_LT(pos_err(kPanda.fk(r.q), target), 1e-6);
    EXPECT_LT(rot_err(kPanda.fk(r.q), target), 1e-8);
  }
}

// The same flange pose with the null space pulled toward two references: two configurations.
TEST(Robot, NullSpaceBiasGivesAnotherConfigurationForTheSamePose) {
  const Joints ic1 = ready();
  const Pose target = kPanda.fk(ic1);
  Joints ref2 = ic1;
  ref2[0] += M_PI / 2;
  robot::IkSettings s;
  s.use_q_ref = true, s.q_ref = ref2, s.max_iterations = 3000;
  const auto r = robot::solve_ik(kPanda, target, ic1, s);
  ASSERT_TRUE(r.converged) << r.error_mm << " mm";
  EXPECT_LT(pos_err(kPanda.fk(r.q), target), 1e-6);
  EXPECT_TRUE(r.within_limits);
  EXPECT_GT((r.q - ic1).norm(), 0.5);  // a genuinely different elbow
}

TEST(Robot, PerturbedArmIsSeededAndWithinTheStatedRanges) {
  const robot::ErrorModelSettings e;
  const auto a = robot::perturbed_arm(kPanda, e, 3), b = robot::perturbed_arm(kPanda, e, 3),
             c = robot::perturbed_arm(kPanda, e, 4);
  EXPECT_EQ(a.fk(ready()).matrix(), b.fk(ready()).matrix());
  EXPECT_NE(a.fk(ready()).matrix(), c.fk(ready()).matrix());
  for (int i = 0; i < 7; ++i) {
    const double da = std::abs(a.joints[i].a_mm - kPanda.joints[i].a_mm);
    const double dal = std::abs(a.joints[i].alpha_rad - kPanda.joints[i].alpha_rad) * 1e3;
    EXPECT_GE(da, e.length_min_mm);
    EXPECT_LE(da, e.length_max_mm);
    EXPECT_GE(dal, e.angle_min_mrad);
    EXPECT_LE(dal, e.angle_max_mrad);
  }
}

// A pose taught in IC1 on the true arm is reproduced exactly by replaying IC1's joints; reaching
// it through the nominal model in other configurations misses, more the further the elbow moves.
TEST(Robot, ModelErrorGrowsWithTheConfigurationChange) {
  int grew = 0;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const auto truth = robot::perturbed_arm(kPanda, {}, seed);
    const Joints ic1 = ready();
    const Pose taught = truth.fk(ic1);  // where the true arm was when the pose was taught
    EXPECT_LT(pos_err(truth.fk(ic1), taught), 1e-9);
    // The controller only knows the nominal model: it believes the taught pose is fk_nominal(ic1).
    const Pose believed = kPanda.fk(ic1);
    std::vector<double> err;
    for (double swing : {0.1, 0.5, 1.5}) {
      robot::IkSettings s;
      s.use_q_ref = true, s.q_ref = ic1, s.max_iterations = 3000;
      s.q_ref[0] += swing;
      const auto r = robot::solve_ik(kPanda, believed, ic1, s);
      ASSERT_TRUE(r.converged);
      err.push_back(pos_err(truth.fk(r.q), taught));
    }
    EXPECT_GT(err.back(), 0.5) << "seed " << seed;  // IC2-like change: millimetres
    grew += err[0] < err[1] && err[1] < err[2];
  }
  EXPECT_GE(grew, 4);  // monotone for (nearly) every arm
}
