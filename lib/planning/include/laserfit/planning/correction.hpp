#pragma once
// The corrective trajectory: a relative Cartesian motion of the flange from its current pose to
// the corrected insertion pose, time-parameterised by a quintic minimum-jerk profile (Flash &
// Hogan 1985: s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5) along the straight line and the geodesic
// rotation, sampled at 1 kHz. Its duration is the shortest one the Cartesian limits allow; the
// samples are checked against the limits and the configured correction amplitude, and a
// trajectory that would exceed them is refused with the reason, never returned.
#include <string>
#include <vector>

#include "laserfit/core/pose.hpp"
#include "laserfit/robot/arm.hpp"

namespace laserfit::planning {

struct CorrectionSettings {
  double max_translation_mm = 5.0;  // refuse larger corrections (a registration gone wrong)
  double max_rotation_deg = 5.0;
  double rate_hz = 1000.0;      // Panda's control rate
  double speed_fraction = 0.1;  // use this fraction of the Cartesian limits (cautious)
  double min_duration_s = 0.05;
  robot::CartesianLimits limits;  // Panda datasheet, mm
  void validate() const;          // throws laserfit::Error on nonsense
};

struct TrajectorySample {
  double t_s = 0;
  Pose T_base_flange;
};

struct Trajectory {
  bool ok = false;
  std::string reason;  // why refused
  double duration_s = 0, translation_mm = 0, rotation_deg = 0;
  double peak_v_mm_s = 0, peak_a_mm_s2 = 0, peak_j_mm_s3 = 0;  // measured on the samples
  double peak_w_rad_s = 0, peak_dw_rad_s2 = 0, peak_ddw_rad_s3 = 0;
  std::vector<TrajectorySample> samples;  // empty when refused
};

Trajectory plan_correction(const Pose& T_base_start, const Pose& T_base_goal,
                           const CorrectionSettings& s);
// Only the limit check of plan_correction: translation_mm, rotation_deg and, when refused, the
// reason (ok stays false; no duration, no samples).
Trajectory check_correction(const Pose& T_base_start, const Pose& T_base_goal,
                            const CorrectionSettings& s);

// The joint path that follows a trajectory (IK per sample, seeded by the previous one), checked
// against the arm's joint position, velocity, acceleration and jerk limits.
struct JointCheck {
  bool ok = false;
  std::string reason;
  std::vector<robot::Joints> q;
};
JointCheck follow_in_joints(const robot::ArmModel& arm, const Trajectory& traj,
                            const robot::Joints& q_start);

// t, x, y, z (mm), qw, qx, qy, qz per line, robot base frame; written atomically.
void write_trajectory_csv(const std::string& path, const Trajectory& traj);

}  // namespace laserfit::planning
