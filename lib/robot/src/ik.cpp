#include "laserfit/robot/ik.hpp"

#include <Eigen/Dense>

namespace laserfit::robot {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Task-space error [dp (mm); dphi (rad)] from the current to the target flange pose.
Vector6d pose_error(const Pose& current, const Pose& target) {
  Vector6d e;
  e.head<3>() = target.translation() - current.translation();
  const Eigen::AngleAxisd aa(target.linear() * current.linear().transpose());
  e.tail<3>() = aa.axis() * aa.angle();
  return e;
}

}  // namespace

IkResult solve_ik(const ArmModel& arm, const Pose& target, const Joints& q_start,
                  const IkSettings& s) {
  IkResult r;
  Joints q = q_start;
  // Rotations are weighed as displacements at 100 mm so that mm and rad are commensurate.
  Vector6d w;
  w << 1, 1, 1, 100, 100, 100;
  // Phase 1 (with a reference): the task and, in its null space, the pull toward q_ref, until the
  // elbow settles. The damped pseudo-inverse's null-space projector is not exact, so phase 2
  // finishes the task alone from there: it converges to the tolerance and keeps the elbow.
  bool settling = s.use_q_ref;
  for (r.iterations = 0; r.iterations < s.max_iterations; ++r.iterations) {
    const Vector6d e = pose_error(arm.fk(q), target);
    r.error_mm = e.head<3>().norm(), r.error_rad = e.tail<3>().norm();
    if (!settling && r.error_mm < s.tolerance_mm && r.error_rad < s.tolerance_rad) {
      r.converged = true;
      break;
    }
    const Jacobian J = w.asDiagonal() * arm.jacobian(q);
    const Eigen::Matrix<double, 6, 6> JJt =
        J * J.transpose() + s.damping * s.damping * Eigen::Matrix<double, 6, 6>::Identity();
    const Eigen::Matrix<double, 7, 6> Jpinv =
        J.transpose() * JJt.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
    Joints dq = Jpinv * (w.asDiagonal() * e);
    if (settling) {
      const Eigen::Matrix<double, 7, 7> N = Eigen::Matrix<double, 7, 7>::Identity() - Jpinv * J;
      const Joints null_step = N * (s.nullspace_gain * (s.q_ref - q));
      dq += null_step;
      settling =
          !(null_step.norm() < 1e-6 && r.error_mm < 1e-3) && r.iterations < s.max_iterations / 2;
    }
    const double big = dq.cwiseAbs().maxCoeff();
    if (big > s.max_step_rad) dq *= s.max_step_rad / big;
    q += dq;
  }
  r.q = q;
  r.within_limits = arm.within_limits(q);
  return r;
}

}  // namespace laserfit::robot
