#pragma once
// Profiles + the arm's flange pose per profile + the hand-eye calibration -> the organized cloud
// that `laserfit register` takes, in the arm's base frame: point j of profile i is
//   p_base = T_base_flange[i] * T_flange_sensor * (x_ij, 0, z_ij),
// the sensor frame being the scanner's (x along the laser line, z the depth, y = 0 on the line).
#include <vector>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/io/profiles.hpp"

namespace laserfit::sensor {

// Width = points per profile, height = profiles, NaN where a profile has no measurement. The
// sensor origin is the middle profile's sensor position (as `laserfit scan` writes it: normals
// are oriented towards it). Throws laserfit::Error when the pose count differs from the profiles'.
PointCloud assemble_scan(const io::Profiles& profiles, const std::vector<Pose>& T_base_flange,
                         const Pose& T_flange_sensor);

}  // namespace laserfit::sensor
