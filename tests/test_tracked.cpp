// A static target trusted earlier in a trial keeps the one turn a later scan cannot pin
// (registration::along_weakest_to, controller::turn_from_tracked).
#include <gtest/gtest.h>

#include <cmath>

#include "laserfit/controller/controller.hpp"

using namespace laserfit;

namespace {

Pose turned_about(const Eigen::Vector3d& axis, double deg, const Eigen::Vector3d& through) {
  Pose M = Pose::Identity();
  M.linear() = Eigen::AngleAxisd(deg * M_PI / 180, axis.normalized()).toRotationMatrix();
  M.translation() = through - M.linear() * through;
  return M;
}

// An `ambiguous` result whose one unobservable direction is a turn about `axis` through `centre`
// (scan frame), with the Hessian's scaling L: [L axis; 0] is a unit eigenvector.
registration::RegistrationResult ambiguous_turn(const Pose& T, const Eigen::Vector3d& axis,
                                                const Eigen::Vector3d& centre, double L) {
  registration::RegistrationResult r;
  r.T_scan_ref = T;
  r.status = registration::Status::Ambiguous, r.unobservable = 1;
  r.weakest_direction << axis.normalized(), Eigen::Vector3d::Zero();
  r.hessian_centre = centre, r.hessian_radius_mm = L;
  return r;
}

double angle_deg(const Pose& A, const Pose& B) {
  return Eigen::AngleAxisd(A.linear().transpose() * B.linear()).angle() * 180 / M_PI;
}

}  // namespace

TEST(Tracked, AlongTheWeakestTurnOnlyThatTurnIsTaken) {
  // The target as this scan measured it: its true pose turned 0.4 deg about a tilted axis through
  // a point 20 mm from the origin (unobservable), and 8 um off along x (observable: kept). The
  // earlier measurement is the true pose. Tolerance: first order in the turn, 0.4 deg over
  // 30 mm is 0.2 mm of arc, its second-order term ~1 um; 0.002 deg.
  Pose truth = Pose::Identity();
  truth.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  truth.translation() = Eigen::Vector3d(400, 90, 250);
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.04, 0.1, 1).normalized();
  const Eigen::Vector3d centre = truth * Eigen::Vector3d(20, 5, -3);
  Pose seen = turned_about(axis, 0.4, centre) * truth;
  seen.pretranslate(Eigen::Vector3d(0.008, 0, 0));
  const auto r = ambiguous_turn(seen, axis, centre, 6.0);
  const Pose fixed = registration::along_weakest_to(r, truth);
  EXPECT_LT(angle_deg(fixed, truth), 0.002);
  Pose want = truth;
  want.pretranslate(Eigen::Vector3d(0.008, 0, 0));
  EXPECT_LT((fixed.translation() - want.translation()).norm(), 0.001);  // mm
  // Toward itself nothing moves.
  EXPECT_LT((registration::along_weakest_to(r, seen).matrix() - seen.matrix()).norm(), 1e-12);
}

TEST(Tracked, OnlyASingleUnpinnedTurnNearTheLastMeasurementIsTaken) {
  const controller::ControllerSettings s;  // 0.5 mm, 0.5 deg
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), centre(10, 0, 0);
  const Pose tracked = Pose::Identity();
  const Pose seen = turned_about(axis, 0.3, centre);
  auto r = ambiguous_turn(seen, axis, centre, 5.0);
  const auto T = controller::turn_from_tracked(r, tracked, s);
  ASSERT_TRUE(T);
  EXPECT_LT(angle_deg(*T, tracked), 1e-3);
  // Not for: two unobservable directions, a slide, a result not pinned by the jackknife, an
  // `ok` or failed one (nothing to take), a turn farther than the target can have moved.
  r.unobservable = 2;
  EXPECT_FALSE(controller::turn_from_tracked(r, tracked, s));
  r.unobservable = 1, r.weakest_direction << 0, 0, 0, 1, 0, 0;
  EXPECT_FALSE(controller::turn_from_tracked(r, tracked, s));
  r = ambiguous_turn(seen, axis, centre, 5.0), r.not_pinned = true;
  EXPECT_FALSE(controller::turn_from_tracked(r, tracked, s));
  r.not_pinned = false, r.status = registration::Status::Failed;
  EXPECT_FALSE(controller::turn_from_tracked(r, tracked, s));
  // 0.6 mm off along x besides the turn: the observable part is this scan's, and it is too far.
  Pose far = seen;
  far.pretranslate(Eigen::Vector3d(0.6, 0, 0));
  EXPECT_FALSE(controller::turn_from_tracked(ambiguous_turn(far, axis, centre, 5.0), tracked, s));
  far.translation().x() -= 0.2;  // 0.4 mm: a sensing arm's repeatability allows it
  EXPECT_TRUE(controller::turn_from_tracked(ambiguous_turn(far, axis, centre, 5.0), tracked, s));
}
