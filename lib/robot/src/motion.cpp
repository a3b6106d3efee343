#include "laserfit/robot/motion.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace laserfit::robot {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

double min_jerk(double x) { return x * x * x * (10 + x * (-15 + 6 * x)); }

}  // namespace

Pose CartesianPath::sample(size_t i) const {
  Pose p = Pose::Identity();
  p.translation() = t.at(i);
  p.linear() = q.at(i).toRotationMatrix();
  return p;
}

CartesianPath plan_cartesian(const Pose& start, const Pose& goal, const MotionSettings& s) {
  const Eigen::Vector3d dp = goal.translation() - start.translation();
  const Eigen::Quaterniond qa(start.linear()), qb(goal.linear());
  const double angle = qa.angularDistance(qb);
  // Duration from the path length (rotations counted at 100 mm), minimum-jerk timing.
  const double T = std::max(s.min_duration_s, (dp.norm() + 100 * angle) / s.speed_mm_s);
  const double dt = 1.0 / s.rate_hz;
  const int n_move = int(std::ceil(T / dt)), n_total = n_move + int(std::ceil(s.settle_s / dt));
  CartesianPath path;
  path.rate_hz = s.rate_hz;
  path.t.reserve(size_t(n_total)), path.q.reserve(size_t(n_total));
  for (int i = 1; i <= n_total; ++i) {
    const double u = min_jerk(std::min(1.0, double(i) / n_move));
    path.t.push_back(start.translation() + u * dp);
    path.q.push_back(qa.slerp(u, qb));
  }
  return path;
}

MotionResult follow_cartesian(const ArmModel& arm, const Joints& q_start, const CartesianPath& path,
                              const Joints& q_ref, const MotionSettings& s) {
  MotionResult r;
  Joints q = q_start;
  const double dt = 1.0 / path.rate_hz;
  Vector6d w;
  w << 1, 1, 1, 100, 100, 100;
  for (size_t i = 0; i < path.size(); ++i) {
    const Pose cur = arm.fk(q);
    Vector6d e;
    e.head<3>() = path.t[i] - cur.translation();
    const Eigen::AngleAxisd aa(path.q[i].toRotationMatrix() * cur.linear().transpose());
    e.tail<3>() = aa.axis() * aa.angle();
    const Jacobian J = w.asDiagonal() * arm.jacobian(q);
    const Eigen::Matrix<double, 6, 6> JJt =
        J * J.transpose() + s.damping * s.damping * Eigen::Matrix<double, 6, 6>::Identity();
    const Eigen::Matrix<double, 7, 6> Jp =
        J.transpose() * JJt.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
    const Eigen::Matrix<double, 7, 7> N = Eigen::Matrix<double, 7, 7>::Identity() - Jp * J;
    // The path error is closed within one cycle; the null-space pull acts at its finite rate.
    Joints dq = Jp * (w.asDiagonal() * e) + N * (s.nullspace_gain * dt * (q_ref - q));
    for (int j = 0; j < 7; ++j) {
      const double vmax = arm.limits.qd_max[j] * dt;
      dq[j] = std::clamp(dq[j], -vmax, vmax);
    }
    q += dq;
    for (int j = 0; j < 7; ++j)
      if (q[j] < arm.limits.q_min[j] || q[j] > arm.limits.q_max[j]) {
        q[j] = std::clamp(q[j], arm.limits.q_min[j], arm.limits.q_max[j]);
        r.limits_ok = false;
      }
  }
  r.q = q;
  r.duration_s = path.duration_s();
  if (path.size() == 0) return r;
  const Pose end = arm.fk(q), goal = path.sample(path.size() - 1);
  r.nominal_error_mm = (end.translation() - goal.translation()).norm();
  r.reached = r.nominal_error_mm < 1e-3 &&
              Eigen::AngleAxisd(end.linear().transpose() * goal.linear()).angle() < 1e-5;
  return r;
}

MotionResult move_cartesian(const ArmModel& arm, const Joints& q_start, const Pose& goal,
                            const Joints& q_ref, const MotionSettings& s) {
  return follow_cartesian(arm, q_start, plan_cartesian(arm.fk(q_start), goal, s), q_ref, s);
}

}  // namespace laserfit::robot
