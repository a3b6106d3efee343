#pragma once
// A 7-DoF serial arm in modified (Craig) Denavit-Hartenberg form, millimetres and radians:
// forward kinematics, the geometric Jacobian, joint limits. ArmModel::panda() is the Franka Emika
// Panda with the official parameters (frankaemika.github.io/docs/control_parameters.html).
#include <Eigen/Core>
#include <array>
#include <string>

#include "laserfit/core/pose.hpp"

namespace laserfit::robot {

using Joints = Eigen::Matrix<double, 7, 1>;    // rad
using Jacobian = Eigen::Matrix<double, 6, 7>;  // rows: v (mm/s per rad/s), omega (rad/s per rad/s)

// Row i: T_{i-1,i} = RotX(alpha) * TransX(a) * RotZ(q_i + theta) * TransZ(d) (Craig's convention;
// the Panda table's a and alpha are a_{i-1}, alpha_{i-1}).
struct DhRow {
  double a_mm = 0, d_mm = 0, alpha_rad = 0, theta_rad = 0;
};

struct JointLimits {
  Joints q_min, q_max;  // rad
  Joints qd_max;        // rad/s
  Joints qdd_max;       // rad/s^2
  Joints qddd_max;      // rad/s^3
};

// Cartesian limits of the flange (Panda datasheet, converted to mm).
struct CartesianLimits {
  double v_mm_s = 1700, a_mm_s2 = 13000, j_mm_s3 = 6.5e6;
  double w_rad_s = 2.5, dw_rad_s2 = 25, ddw_rad_s3 = 12500;
};

struct ArmModel {
  std::string name;
  std::array<DhRow, 7> joints;
  DhRow flange;  // fixed transform from joint 7 to the flange
  JointLimits limits;
  CartesianLimits cartesian;

  static ArmModel panda();
  Pose fk(const Joints& q) const;                               // T_base_flange
  Pose fk(const Joints& q, std::array<Pose, 8>* frames) const;  // + every joint frame, flange last
  Jacobian jacobian(const Joints& q) const;  // geometric, base frame, at the flange origin
  bool within_limits(const Joints& q, double margin_rad = 0) const;
};

}  // namespace laserfit::robot
