#pragma once
// Inverse kinematics by damped least squares (Wampler 1986; Buss 2004, eq. 11) with a null-space
// bias toward a reference configuration: the 7th DoF lets the same flange pose be reached with
// different elbows, which is how the paper obtains IC1 and IC2.
#include "laserfit/robot/arm.hpp"

namespace laserfit::robot {

struct IkSettings {
  int max_iterations = 300;
  double damping = 0.5;           // lambda of (J J^T + lambda^2 W), mm-scaled
  double tolerance_mm = 1e-6;     // position error to stop at
  double tolerance_rad = 1e-8;    // orientation error to stop at
  double max_step_rad = 0.2;      // largest joint step per iteration
  double nullspace_gain = 0.2;    // pull toward q_ref within the task's null space
  Joints q_ref = Joints::Zero();  // preferred configuration (null-space target)
  bool use_q_ref = false;
};

struct IkResult {
  Joints q = Joints::Zero();
  bool converged = false, within_limits = false;
  int iterations = 0;
  double error_mm = 0, error_rad = 0;
};

IkResult solve_ik(const ArmModel& arm, const Pose& T_base_flange, const Joints& q_start,
                  const IkSettings& s = {});

}  // namespace laserfit::robot
