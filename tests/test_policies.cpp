// The policies laserfit adds to Algorithm 1 (lib/registration/src/policies.cpp), each tested alone
// on hand-made attempts: what it decides, and that it leaves alone what it should not touch.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "driver.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "test_util.hpp"

using namespace laserfit;
namespace reg = laserfit::registration;

namespace {

Pose shifted(const Pose& T, const Eigen::Vector3d& by_mm) {
  Pose out = T;
  out.translation() += by_mm;
  return out;
}

// A noise-free view of the USB plug at a known pose and its reference cloud.
struct Plug {
  PointCloud scan, ref;
  Pose T_scan_ref;
  reg::RegistrationSettings s;
};
const Plug& plug() {
  static const Plug p = [] {
    Plug out;
    const TriMesh m =
        cad::import_cad(std::string(LASERFIT_SOURCE_DIR) + "/cad/usb_a_plug.ply").mesh;
    out.T_scan_ref =
        pose_from_tq({512.3, -40.7, 101.9},
                     Eigen::Quaterniond(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitZ())));
    sampling::SamplingSettings ss;
    ss.count = 60000, ss.seed = 11;
    out.ref = sampling::sample_uniform(m, ss);
    sampling::ViewSettings v;
    const Eigen::Vector3d c = m.bbox().center().cast<double>();
    v.T_mesh_sensor.push_back(look_at(c + Eigen::Vector3d(0.3, -0.5, 1.0).normalized() * 95, c));
    ss.count = 40000, ss.seed = 99;
    out.scan = sampling::sample_visible(m, v, ss);
    for (auto& q : out.scan.points) q = (out.T_scan_ref * q.cast<double>()).cast<float>();
    out.scan.normals.clear();
    out.s.pre.use_viewpoint = true;
    out.s.pre.viewpoint = out.T_scan_ref * v.T_mesh_sensor[0].translation();
    return out;
  }();
  return p;
}

reg::Candidate candidate(const Pose& T, double fitness_mm2, double overlap) {
  return {T, reg::Fit{fitness_mm2, std::sqrt(fitness_mm2), overlap, 0}};
}

}  // namespace

TEST(Policies, ConfirmationNeedsASecondAttemptThatAgrees) {
  const Plug& P = plug();
  reg::RegistrationResult r0;
  const reg::Problem p = reg::prepare_problem(P.scan, P.ref, P.s, r0);
  const auto best = candidate(P.T_scan_ref, 1e-6, 0.95);
  reg::Attempts a;
  a.good = {best};
  reg::RegistrationResult r;
  r.status = reg::Status::Ok;
  reg::require_confirmation(p, a, best, r);
  EXPECT_EQ(r.status, reg::Status::Failed) << "one attempt alone is no confirmation";
  // A second attempt 1 um away agrees (restart_agreement_mm, 20 um RMS along the normals).
  a.good.push_back(candidate(shifted(P.T_scan_ref, {0.001, 0, 0}), 1e-6, 0.95));
  r.status = reg::Status::Ok;
  reg::require_confirmation(p, a, best, r);
  EXPECT_EQ(r.status, reg::Status::Ok) << r.reason;
  // One 0.5 mm away does not.
  a.good.back() = candidate(shifted(P.T_scan_ref, {0.5, 0, 0}), 1e-6, 0.95);
  reg::require_confirmation(p, a, best, r);
  EXPECT_EQ(r.status, reg::Status::Failed);
}

TEST(Policies, RivalsThatFitAsWellMakeItAmbiguous) {
  const Plug& P = plug();
  reg::RegistrationResult r0;
  const reg::Problem p = reg::prepare_problem(P.scan, P.ref, P.s, r0);
  const auto best = candidate(P.T_scan_ref, 1e-6, 0.95);
  reg::Attempts a;
  a.good = {best, candidate(shifted(P.T_scan_ref, {1, 0, 0}), 1.2e-6, 0.94)};  // 1 mm off, as good
  reg::RegistrationResult r;
  r.status = reg::Status::Ok;
  reg::reject_rivals(p, a, best, r);
  EXPECT_EQ(r.status, reg::Status::Ambiguous);
  // A rival explaining less of the scan (below fits_as_well's 98 % of the overlap) is no rival.
  a.good.back().fit.overlap = 0.9;
  r.status = reg::Status::Ok;
  reg::reject_rivals(p, a, best, r);
  EXPECT_EQ(r.status, reg::Status::Ok) << r.reason;
}

TEST(Policies, PolishFailsAPoseOffTheRobustMinimum) {
  const Plug& P = plug();
  reg::RegistrationSettings s = P.s;
  s.refine.method = reg::Refiner::PointToPlane;  // polish checks the PCL refiners only
  reg::RegistrationResult r0;
  const reg::Problem p = reg::prepare_problem(P.scan, P.ref, s, r0);
  reg::RegistrationResult r;
  r.status = reg::Status::Ok;
  reg::polish(p, candidate(P.T_scan_ref, 1e-6, 0.95), r);  // the truth: moves < polish_mm (20 um)
  EXPECT_EQ(r.status, reg::Status::Ok) << r.reason;
  reg::polish(p, candidate(shifted(P.T_scan_ref, {0, 0.2, 0}), 1e-6, 0.95), r);  // 200 um off
  EXPECT_EQ(r.status, reg::Status::Failed);
  EXPECT_NE(r.reason.find("not at the minimum"), std::string::npos) << r.reason;
}

TEST(Policies, PlateauSpansTheAttemptsThatFitAsWell) {
  const Plug& P = plug();
  reg::RegistrationResult r0;
  const reg::Problem p = reg::prepare_problem(P.scan, P.ref, P.s, r0);
  const auto best = candidate(P.T_scan_ref, 1e-6, 0.95);
  reg::Attempts a;
  a.good = {best, candidate(shifted(P.T_scan_ref, {0.5, 0, 0}), 1e-6, 0.95),
            candidate(shifted(P.T_scan_ref, {-0.3, 0, 0}), 1.1e-6, 0.95),
            candidate(shifted(P.T_scan_ref, {2.0, 0, 0}), 1e-5, 0.95)};  // 10x the fitness: out
  reg::RegistrationResult r;
  r.status = reg::Status::Ambiguous, r.flat = 1, r.T_scan_ref = P.T_scan_ref;
  r.weakest_direction << 0, 0, 0, 1, 0, 0;  // flat along the scan's x
  reg::measure_plateau(p, a, best, r);
  EXPECT_NEAR(r.flat_from_mm, -0.3, 1e-9);
  EXPECT_NEAR(r.flat_to_mm, 0.5, 1e-9);
}

TEST(Policies, AnAmbiguousPoseMovesToTheEqualAttemptNearestThePrior) {
  const Plug& P = plug();
  reg::RegistrationSettings s = P.s;
  s.prior = P.T_scan_ref;
  reg::RegistrationResult r0;
  const reg::Problem p = reg::prepare_problem(P.scan, P.ref, s, r0);
  auto best = candidate(shifted(P.T_scan_ref, {0.4, 0, 0}), 1e-6, 0.95);
  reg::Attempts a;
  a.good = {best, candidate(P.T_scan_ref, 1.2e-6, 0.95)};
  reg::RegistrationResult r;
  r.status = reg::Status::Ambiguous, r.T_scan_ref = best.T_scan_ref;
  reg::prefer_prior(p, a, best, r);
  EXPECT_EQ(best.T_scan_ref.matrix(), P.T_scan_ref.matrix());
  EXPECT_EQ(r.T_scan_ref.matrix(), P.T_scan_ref.matrix());  // and re-assessed there
  EXPECT_GT(r.overlap, 0.5);
  // Without a prior it keeps the pose it had.
  const reg::Problem q = reg::prepare_problem(P.scan, P.ref, P.s, r0);
  best = candidate(shifted(P.T_scan_ref, {0.4, 0, 0}), 1e-6, 0.95);
  r.status = reg::Status::Ambiguous, r.T_scan_ref = best.T_scan_ref;
  reg::prefer_prior(q, a, best, r);
  EXPECT_EQ(r.T_scan_ref.matrix(), shifted(P.T_scan_ref, {0.4, 0, 0}).matrix());
}

TEST(Policies, EachCanBeSwitchedOffInTheDriver) {
  // All policies off is Algorithm 1 with the trust assessment alone: the plug still registers.
  const Plug& P = plug();
  reg::RegistrationSettings s = P.s;
  s.q0 = Eigen::Quaterniond(P.T_scan_ref.rotation());
  s.policies = {false, false, false, false, false, false, false, false, false};
  s.trust.slide_range_mm = 0, s.trust.jackknife_blocks = 0;
  const auto r = reg::register_cloud(P.scan, P.ref, s);
  ASSERT_NE(r.status, reg::Status::Failed) << r.reason;
  EXPECT_LT((r.T_scan_ref.translation() - P.T_scan_ref.translation()).norm(), 0.02);  // 20 um
  EXPECT_EQ(r.sigma_origin_mm, 0.0);  // the jackknife did not run
}

TEST(Policies, TheEntryPointComposesTheStages) {
  // register_scan is register_cloud with segmentation off and register_segmented with it on
  // (bit-identical poses), and says which candidate part it registered.
  const Plug& P = plug();
  reg::RegistrationSettings s = P.s;
  s.q0 = Eigen::Quaterniond(P.T_scan_ref.rotation());
  s.segment.enabled = false;
  const auto whole = reg::register_scan(P.scan, P.ref, s);
  EXPECT_EQ(whole.T_scan_ref.matrix(), reg::register_cloud(P.scan, P.ref, s).T_scan_ref.matrix());
  EXPECT_EQ(whole.part, -1);
  s.segment.enabled = true, s.segment.max_clusters = 2;
  int cluster = -2;
  const auto seg = reg::register_segmented(P.scan, P.ref, s, 2, &cluster);
  const auto entry = reg::register_scan(P.scan, P.ref, s);
  EXPECT_EQ(entry.T_scan_ref.matrix(), seg.T_scan_ref.matrix());
  EXPECT_EQ(entry.part, cluster);
  EXPECT_GE(entry.part, 0);
  s.segment.max_clusters = 0;
  EXPECT_THROW(reg::register_scan(P.scan, P.ref, s), Error);
}

TEST(Policies, RefinedFromThePriorAloneAnOkNeedsResidualsThatLookLikeNoise) {
  // Refine-only (no coarse stage, nothing confirms the pose): the o2ac panel slid 9.5 mm along
  // its plate fitted 98 % of its scan to 3 um and the rest to ~0.5 mm (RMSE 90 um, robust sigma
  // 3.3 um): failed. The true pose (RMSE 4.0 um, sigma 3.3 um) stays ok, as does a noise-free
  // fit under the floor, and with a coarse stage the policy leaves the decision alone.
  const Plug& P = plug();
  reg::RegistrationSettings s = P.s;
  s.prior = P.T_scan_ref, s.skip_coarse = true;
  reg::RegistrationResult r0;
  const reg::Problem p = reg::prepare_problem(P.scan, P.ref, s, r0);
  ASSERT_FALSE(p.coarse);
  auto decide = [](const reg::Problem& q, double rmse_um, double sigma_um) {
    reg::RegistrationResult r;
    r.status = reg::Status::Ok;
    r.inlier_rmse_mm = rmse_um * 1e-3, r.residual_sigma_mm = sigma_um * 1e-3;
    reg::require_consistent_residuals(q, r);
    return r;
  };
  const auto slid = decide(p, 89.8, 3.3);
  EXPECT_EQ(slid.status, reg::Status::Failed);
  EXPECT_NE(slid.reason.find("residuals are not noise"), std::string::npos) << slid.reason;
  EXPECT_EQ(decide(p, 4.0, 3.3).status, reg::Status::Ok);
  EXPECT_EQ(decide(p, 18.8, 2.8).status, reg::Status::Ok);  // shiny faces' outliers: ratio 6.7
  EXPECT_EQ(decide(p, 2.0, 0.01).status, reg::Status::Ok);  // under rmse_floor_mm (5 um)
  s.skip_coarse = false;
  const reg::Problem global = reg::prepare_problem(P.scan, P.ref, s, r0);
  EXPECT_EQ(decide(global, 89.8, 3.3).status, reg::Status::Ok);  // confirmation's job there
}

TEST(Policies, RobustSigmaIsTheNoiseBlindToAMisfitMinority) {
  // Gaussian residuals of 3 um: within 5 % of 3 um; with 5 % of them 0.5 mm off, within 10 %.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0, 0.003);
  std::vector<reg::Match> m(20000);
  for (auto& x : m) x.n = Eigen::Vector3d::UnitZ(), x.q = Eigen::Vector3d(0, 0, n(rng));
  EXPECT_NEAR(reg::robust_sigma(m), 0.003, 0.00015);
  for (size_t i = 0; i < m.size(); i += 20) m[i].q.z() = 0.5;
  EXPECT_NEAR(reg::robust_sigma(m), 0.003, 0.0003);
  EXPECT_TRUE(std::isinf(reg::robust_sigma({})));
}

// Not a policy but the driver's first stage: a scan read in the wrong unit (metres or micrometres
// taken as mm, a factor 1000) is refused with both extents named; the right unit passes the check.
TEST(Driver, RefusesAScanInAnotherUnit) {
  const Plug& p = plug();
  EXPECT_NO_THROW(reg::check_scale(p.scan, p.ref));
  for (const float k : {1e-3f, 1e3f}) {
    PointCloud scan = p.scan;
    for (auto& q : scan.points) q *= k;
    try {
      reg::register_scan(scan, p.ref, p.s);
      FAIL() << "a scan scaled by " << k << " was registered";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("not the same unit"), std::string::npos) << what;
      EXPECT_NE(what.find("--unit"), std::string::npos) << what;
    }
  }
}
