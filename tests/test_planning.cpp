// Corrective trajectories: a property test over random corrections (never a limit violated, start
// and goal hit exactly), refusals above the amplitude limit, the minimum-jerk peak velocity.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>

#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/planning/correction.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {

robot::Joints ready() {
  robot::Joints q;
  q << 0, -M_PI / 4, 0, -3 * M_PI / 4, 0, M_PI / 2, M_PI / 4;
  return q;
}

Pose random_correction(const Pose& start, double max_mm, double max_deg, laserfit::Mt19937_64& g) {
  Eigen::Vector3d t, axis;
  do t = Eigen::Vector3d(uniform01(g), uniform01(g), uniform01(g)) * 2 - Eigen::Vector3d::Ones();
  while (t.norm() > 1);
  do axis = Eigen::Vector3d(uniform01(g), uniform01(g), uniform01(g)) * 2 - Eigen::Vector3d::Ones();
  while (axis.norm() > 1 || axis.norm() < 1e-3);
  Pose goal = start;
  goal.translation() += t * max_mm;
  goal.linear() =
      start.linear() *
      Eigen::AngleAxisd(uniform01(g) * max_deg * M_PI / 180, axis.normalized()).toRotationMatrix();
  return goal;
}

}  // namespace

// Property: for 200 random corrections within the amplitude limit, the plan is accepted, starts
// and ends exactly (1e-9 mm / 1e-9 rad), is sampled at 1 kHz, stays within every Cartesian limit
// on its samples, and the Panda follows it within every joint limit.
TEST(Planning, RandomCorrectionsNeverViolateTheLimits) {
  const auto arm = robot::ArmModel::panda();
  const Pose start = arm.fk(ready());
  planning::CorrectionSettings s;
  laserfit::Mt19937_64 g(5);
  for (int k = 0; k < 200; ++k) {
    const Pose goal = random_correction(start, s.max_translation_mm, s.max_rotation_deg, g);
    const auto tr = planning::plan_correction(start, goal, s);
    ASSERT_TRUE(tr.ok) << tr.reason;
    EXPECT_LT((tr.samples.front().T_base_flange.matrix() - start.matrix()).norm(), 1e-9);
    EXPECT_LT((tr.samples.back().T_base_flange.translation() - goal.translation()).norm(), 1e-9);
    EXPECT_LT(
        Eigen::AngleAxisd(tr.samples.back().T_base_flange.linear().transpose() * goal.linear())
            .angle(),
        1e-9);
    EXPECT_NEAR(tr.samples[1].t_s - tr.samples[0].t_s, 1e-3, 1e-12);
    const auto& L = s.limits;
    EXPECT_LE(tr.peak_v_mm_s, L.v_mm_s);
    EXPECT_LE(tr.peak_a_mm_s2, L.a_mm_s2);
    EXPECT_LE(tr.peak_j_mm_s3, L.j_mm_s3);
    EXPECT_LE(tr.peak_w_rad_s, L.w_rad_s);
    EXPECT_LE(tr.peak_dw_rad_s2, L.dw_rad_s2);
    EXPECT_LE(tr.peak_ddw_rad_s3, L.ddw_rad_s3);
    if (k < 20) {  // IK per sample is the slow part
      const auto jc = planning::follow_in_joints(arm, tr, ready());
      EXPECT_TRUE(jc.ok) << jc.reason;
    }
  }
}

TEST(Planning, CorrectionsAboveTheAmplitudeLimitAreRefused) {
  test::TempDir dir;
  const Pose start = robot::ArmModel::panda().fk(ready());
  planning::CorrectionSettings s;
  Pose far = start;
  far.translation().x() += s.max_translation_mm * 1.01;
  auto tr = planning::plan_correction(start, far, s);
  EXPECT_FALSE(tr.ok);
  EXPECT_TRUE(tr.samples.empty());
  EXPECT_NE(tr.reason.find("exceeds"), std::string::npos) << tr.reason;
  Pose turned = start;
  turned.linear() = start.linear() * Eigen::AngleAxisd((s.max_rotation_deg + 0.1) * M_PI / 180,
                                                       Eigen::Vector3d::UnitZ())
                                         .toRotationMatrix();
  EXPECT_FALSE(planning::plan_correction(start, turned, s).ok);
  EXPECT_THROW(planning::write_trajectory_csv(dir / "t.csv", tr), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "t.csv"));
}

// Tolerance: the sampled peak velocity is the minimum-jerk value 1.875 D / T within 0.5 %.
TEST(Planning, MinimumJerkProfileAndCsv) {
  test::TempDir dir;
  const Pose start = robot::ArmModel::panda().fk(ready());
  Pose goal = start;
  goal.translation() += Eigen::Vector3d(2, -1, 0.5);
  planning::CorrectionSettings s;
  const auto tr = planning::plan_correction(start, goal, s);
  ASSERT_TRUE(tr.ok);
  EXPECT_NEAR(tr.peak_v_mm_s, 1.875 * tr.translation_mm / tr.duration_s, 0.005 * tr.peak_v_mm_s);
  planning::write_trajectory_csv(dir / "t.csv", tr);
  std::ifstream in(dir / "t.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz");
  size_t rows = 0;
  for (std::string l; std::getline(in, l);) ++rows;
  EXPECT_EQ(rows, tr.samples.size());
}
