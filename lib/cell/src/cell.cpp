#include "laserfit/cell/cell.hpp"

#include <Eigen/Geometry>

namespace laserfit::cell {

Pose error_pose(const RigidError& e) {
  Pose T = Pose::Identity();
  T.translation() = Eigen::Vector3d(e[0], e[1], e[2]);
  const Eigen::Vector3d r = Eigen::Vector3d(e[3], e[4], e[5]) * M_PI / 180;
  if (r.norm() > 0) T.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  return T;
}

Cell::Cell(const CellSettings& settings, uint64_t robot_seed)
    : s(settings), nominal(robot::ArmModel::panda()) {
  trueA = robot::perturbed_arm(nominal, s.arm_errors, 2 * robot_seed + 1);
  trueS = robot::perturbed_arm(nominal, s.arm_errors, 2 * robot_seed + 2);
  T_world_baseA_believed = s.T_world_baseA;
  T_world_baseA_true = s.T_world_baseA * error_pose(s.baseA_error);
  T_flange_part_true = s.T_flange_part * error_pose(s.grasp_error);
  T_flange_sensor_true = s.T_flange_sensor * error_pose(s.sensor_error);
}

Pose Cell::part_true(const robot::Joints& qA, robot::Repeatability& rep, Mt19937_64& g) const {
  return T_world_baseA_true * rep.reach(trueA.fk(qA), g) * T_flange_part_true;
}

Pose Cell::part_believed(const robot::Joints& qA) const {
  return part_believed_from_flange(nominal.fk(qA));
}

Pose Cell::part_believed_from_flange(const Pose& T_baseA_flange) const {
  return T_world_baseA_believed * T_baseA_flange * s.T_flange_part;
}

Pose Cell::flange_for_part(const Pose& T_world_part) const {
  return T_world_baseA_believed.inverse() * T_world_part * s.T_flange_part.inverse();
}

Insertion check_insertion(const CellSettings& s, const Pose& T_world_target,
                          const Pose& T_world_part) {
  const Pose P = T_world_target.inverse() * T_world_part;  // part in the target frame
  const Pose& Q = s.T_target_part_insert;                  // where it must go
  const Eigen::Vector3d n = Q.linear().col(2), d = P.linear().col(2);
  Insertion r;
  r.angle_deg = std::acos(std::clamp(n.dot(d), -1.0, 1.0)) * 180 / M_PI;
  r.depth_mm = (P.translation() - Q.translation()).dot(n);
  if (std::abs(d.dot(n)) < 1e-6) return r;  // parallel to the mouth: no crossing
  // Where the part's axis crosses the mouth plane, in the insertion frame.
  const double lambda = -(P.translation() - Q.translation()).dot(n) / d.dot(n);
  const Eigen::Vector3d c =
      Q.linear().transpose() * (P.translation() + lambda * d - Q.translation());
  r.x_mm = c.x(), r.y_mm = c.y();
  // Aligned is not inserted: a tip that stopped above the mouth has not entered (the laser
  // strategy's last move goes to the measured insertion point, pushed on only by push_mm).
  r.success = std::abs(r.x_mm) <= s.clearance.x_mm && std::abs(r.y_mm) <= s.clearance.y_mm &&
              r.angle_deg <= s.clearance.angle_deg && r.depth_mm >= -s.clearance.depth_mm;
  return r;
}

}  // namespace laserfit::cell
