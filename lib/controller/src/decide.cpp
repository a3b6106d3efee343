// Decisions from measurements: which registrations to trust, the relative correction, its plan.
#include <Eigen/Geometry>
#include <algorithm>
#include <sstream>

#include "laserfit/controller/controller.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::controller {

bool acceptable(const registration::RegistrationResult& r, const std::string& weak_rot,
                const std::string& weak_trans, const Pose& T, std::string* why) {
  if (r.status == registration::Status::Ok) return true;
  if (r.status == registration::Status::Ambiguous && r.unobservable <= 2) {
    auto axis = [&](const std::string& a) {
      return Eigen::Vector3d(T.linear() * *registration::named_axis(a));
    };
    if (!weak_rot.empty() && registration::weakest_is_rotation_about(r, axis(weak_rot)))
      return true;
    if (!weak_trans.empty() && registration::weakest_is_translation_along(r, axis(weak_trans)))
      return true;
  }
  *why = std::string(registration::status_name(r.status)) +
         (r.reason.empty() ? "" : " (" + r.reason + ")");
  return false;
}

Correction compute_correction(const Measurement& m, const Pose& T_target_part_goal,
                              bool with_orientation, bool with_axial) {
  const Pose goal = m.T_scan_target * T_target_part_goal;  // where the part must be, scan frame
  Correction c;
  Eigen::Vector3d dt = goal.translation() - m.T_scan_part.translation();
  const Eigen::Vector3d axis = goal.linear().col(2);  // the insertion axis
  // Not along the part's own axis where the scan could not fix it, or where the caller says the
  // target hides the part's end (the measured end is short there).
  if (m.part_axial_unknown || !with_axial) {
    const Eigen::Vector3d a = m.T_scan_part.linear().col(2);
    dt -= a * a.dot(dt);
  }
  c.lateral_mm = (dt - axis * axis.dot(dt)).norm();
  c.axial_mm = axis.dot(dt);
  c.axis = axis;
  Eigen::Matrix3d dR = goal.linear() * m.T_scan_part.linear().transpose();
  if (m.target_prior_spin_axis) {
    // The target's spin about w is the prior's: in the scan frame it is off by the sensing arm's
    // orientation error (degrees), so the goal axis is too. Only the part axis' angle to w is
    // measured: tilt the part axis in the plane of it and w until that angle is the goal's.
    const Eigen::Vector3d& w = *m.target_prior_spin_axis;
    const Eigen::Vector3d a = m.T_scan_part.linear().col(2), k = a.cross(w);
    const double tilt =
        std::acos(std::clamp(a.dot(w), -1.0, 1.0)) - std::acos(std::clamp(axis.dot(w), -1.0, 1.0));
    dR = k.norm() > 1e-9 ? Eigen::AngleAxisd(tilt, k.normalized()).toRotationMatrix()
                         : Eigen::Matrix3d::Identity();
  }
  c.angle_deg = Eigen::AngleAxisd(dR).angle() * 180 / M_PI;
  if (with_orientation) {
    // Rotate about the part's tip, then translate: the tip lands on the goal.
    c.delta.linear() = dR;
    c.delta.translation() = m.T_scan_part.translation() + dt - dR * m.T_scan_part.translation();
  } else {
    c.delta.translation() = dt;
  }
  return c;
}

Correction limit_axial(Correction c, double max_mm) {
  const double excess = c.axial_mm - std::clamp(c.axial_mm, -max_mm, max_mm);
  c.delta.translation() -= c.axis * excess;  // the tip lands `excess` short of the goal
  c.axial_mm -= excess;
  return c;
}

ControllerSettings settings_for(const cell::CellSettings& cs) {
  ControllerSettings s;
  s.correction.max_translation_mm = cs.max_correction_mm;
  s.correction.max_rotation_deg = cs.max_correction_deg;
  return s;
}

namespace {
// delta acts in the world (the scan frame); in A's base it is conjugated by the believed base
// transform, so only its rotation part matters for a translation: calibration errors cancel.
Pose goal_in_base(const cell::Cell& c, const Pose& T_baseA_flange, const Pose& delta) {
  const Pose& B = c.T_world_baseA_believed;
  return B.inverse() * delta * B * T_baseA_flange;
}
}  // namespace

planning::Trajectory plan(const cell::Cell& c, const Pose& T_baseA_flange, const Pose& delta,
                          const ControllerSettings& s) {
  return planning::plan_correction(T_baseA_flange, goal_in_base(c, T_baseA_flange, delta),
                                   s.correction);
}

planning::Trajectory plan_folded(const cell::Cell& c, const Pose& T_baseA_flange,
                                 const Pose& correction, const Pose& step,
                                 const ControllerSettings& s) {
  const planning::Trajectory alone = planning::check_correction(
      T_baseA_flange, goal_in_base(c, T_baseA_flange, correction), s.correction);
  if (!alone.reason.empty()) return alone;
  ControllerSettings with_step = s;
  with_step.correction.max_translation_mm += step.translation().norm();
  with_step.correction.max_rotation_deg += Eigen::AngleAxisd(step.linear()).angle() * 180 / M_PI;
  return plan(c, T_baseA_flange, step * correction, with_step);
}

}  // namespace laserfit::controller
