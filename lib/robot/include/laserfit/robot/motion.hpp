#pragma once
// Execution of a Cartesian motion the way a Cartesian position controller does it: resolved-rate
// control at 1 kHz along a minimum-jerk straight-line path, computed with the *nominal* model
// (all the controller knows), with a null-space pull toward a reference configuration (the
// paper's IC1 / IC2 bias) and the joint velocity limits respected. The joints it ends in depend
// on where it started (the null-space pull has a finite gain): on a true arm that differs from
// the model, so does the pose reached.
#include <vector>

#include "laserfit/robot/arm.hpp"

namespace laserfit::robot {

struct MotionSettings {
  double rate_hz = 1000;
  double speed_mm_s = 150;  // path speed (average over the minimum-jerk profile)
  double min_duration_s = 0.2;
  double nullspace_gain = 2.0;  // 1/s: pull toward q_ref within the task's null space
  double settle_s = 0.3;        // hold the goal this long at the end (the error converges)
  double damping = 0.5;         // damped least squares (mm-scaled)
};

struct MotionResult {
  Joints q = Joints::Zero();  // joints at the end
  bool reached = false;       // nominal flange within 1 um / 1e-5 rad of the goal
  bool limits_ok = true;      // never clamped at a joint position limit
  double duration_s = 0, nominal_error_mm = 0;
};

// The reference a Cartesian motion follows, sampled at the controller's rate: sample i is the
// flange pose (base frame) at t = (i + 1) / rate_hz; the last ones hold the goal (settling).
// Translation and unit quaternion (w, x, y, z) as the path is interpolated, so that the samples
// cross a wire unchanged.
struct CartesianPath {
  double rate_hz = 1000;
  std::vector<Eigen::Vector3d> t;     // mm
  std::vector<Eigen::Quaterniond> q;  // unit
  size_t size() const { return t.size(); }
  double duration_s() const { return double(t.size()) / rate_hz; }
  Pose sample(size_t i) const;
};

// The straight minimum-jerk path from `start` to `goal` (s: rate, speed, minimum duration,
// settling).
CartesianPath plan_cartesian(const Pose& T_base_flange_start, const Pose& T_base_flange_goal,
                             const MotionSettings& s = {});

// The arm's controller following `path` from the joints `q_start` on its model `nominal` (s: the
// null-space gain and damping; the path carries its own rate).
MotionResult follow_cartesian(const ArmModel& nominal, const Joints& q_start,
                              const CartesianPath& path, const Joints& q_ref,
                              const MotionSettings& s = {});

// plan_cartesian from where the model puts the flange, then follow_cartesian.
MotionResult move_cartesian(const ArmModel& nominal, const Joints& q_start,
                            const Pose& T_base_flange_goal, const Joints& q_ref,
                            const MotionSettings& s = {});

}  // namespace laserfit::robot
