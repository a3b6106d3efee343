#pragma once
// Poses are doubles: 4x4 homogeneous matrices or (t [mm], unit quaternion w,x,y,z). Name them by
// frame: T_base_sensor maps sensor coordinates into the base frame.
#include <Eigen/Geometry>
#include <array>
#include <string>

namespace laserfit {

using Pose = Eigen::Isometry3d;

// "x y z qw qx qy qz" (7 numbers, mm) or a row-major 4x4 (16 numbers); commas allowed.
// Throws laserfit::Error naming `what` on a malformed or non-rigid pose.
Pose parse_pose(const std::string& text, const std::string& what = "pose");
Pose pose_from_tq(const Eigen::Vector3d& t_mm, const Eigen::Quaterniond& q);
// (x, y, z, qw, qx, qy, qz) with qw >= 0, the representation written to every output file.
std::array<double, 7> pose_to_tq(const Pose& T);
std::string pose_to_string(const Pose& T);  // "x y z qw qx qy qz"

// Geodesic angle between two rotations (rad) — the orientation distance d_phi used by the
// paper's Algorithm 1 (line 5) to gate RANSAC hypotheses.
double rotation_angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

// A viewing pose: sensor at `eye` (mm) looking at `target`, with the sensor's x axis (the laser
// line) as close as possible to `x_hint`. Returns T_ref_sensor (z = viewing direction).
Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
             const Eigen::Vector3d& x_hint = Eigen::Vector3d::UnitX());

}  // namespace laserfit
