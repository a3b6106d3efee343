#include <cmath>
#include <sstream>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/planning/correction.hpp"
#include "laserfit/robot/ik.hpp"

namespace laserfit::planning {

JointCheck follow_in_joints(const robot::ArmModel& arm, const Trajectory& traj,
                            const robot::Joints& q_start) {
  JointCheck c;
  if (!traj.ok || traj.samples.size() < 2) {
    c.reason = "no trajectory to follow";
    return c;
  }
  robot::Joints q = q_start;
  robot::IkSettings ik;
  ik.tolerance_mm = 1e-4, ik.tolerance_rad = 1e-6, ik.max_iterations = 50;
  for (const auto& s : traj.samples) {
    const auto r = robot::solve_ik(arm, s.T_base_flange, q, ik);
    if (!r.converged) {
      std::ostringstream m;
      m << "IK does not reach the sample at t = " << s.t_s << " s (" << r.error_mm << " mm off)";
      c.reason = m.str();
      return c;
    }
    q = r.q;
    c.q.push_back(q);
  }
  const double dt = traj.samples[1].t_s - traj.samples[0].t_s;
  const auto& L = arm.limits;
  auto fail = [&](const char* what, size_t i, int j) {
    std::ostringstream m;
    m << "joint " << j + 1 << " exceeds its " << what << " limit at t = " << traj.samples[i].t_s
      << " s";
    c.reason = m.str();
    return c;
  };
  for (size_t i = 0; i < c.q.size(); ++i)
    for (int j = 0; j < 7; ++j) {
      if (c.q[i][j] < L.q_min[j] || c.q[i][j] > L.q_max[j]) return fail("position", i, j);
      if (i >= 1 && std::abs(c.q[i][j] - c.q[i - 1][j]) / dt > L.qd_max[j])
        return fail("velocity", i, j);
      if (i >= 2 &&
          std::abs(c.q[i][j] - 2 * c.q[i - 1][j] + c.q[i - 2][j]) / (dt * dt) > L.qdd_max[j])
        return fail("acceleration", i, j);
      if (i >= 3 && std::abs(c.q[i][j] - 3 * c.q[i - 1][j] + 3 * c.q[i - 2][j] - c.q[i - 3][j]) /
                            (dt * dt * dt) >
                        L.qddd_max[j])
        return fail("jerk", i, j);
    }
  c.ok = true;
  return c;
}

void write_trajectory_csv(const std::string& path, const Trajectory& traj) {
  if (!traj.ok) throw Error(path, "refusing to write a refused trajectory: " + traj.reason);
  std::ostringstream o;
  o.precision(12);
  o << "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  for (const auto& s : traj.samples) {
    const auto v = pose_to_tq(s.T_base_flange);
    o << s.t_s << ',' << v[0] << ',' << v[1] << ',' << v[2] << ',' << v[3] << ',' << v[4] << ','
      << v[5] << ',' << v[6] << '\n';
  }
  write_file_atomic(path, o.str());
}

}  // namespace laserfit::planning
