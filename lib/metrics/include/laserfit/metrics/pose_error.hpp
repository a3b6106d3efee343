#pragma once
// Pose errors against ground truth, modulo the object's symmetries as the BOP toolkit does
// (Hodan et al. 2020, MSSD: the maximum surface distance, minimised over the symmetry
// transformations that leave the object's appearance unchanged). All lengths mm.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "laserfit/core/pose.hpp"

namespace laserfit::metrics {

// The symmetries of an object about an axis through its frame's origin (object frame).
struct Symmetry {
  enum class Kind { None, Discrete, Continuous } kind = Kind::None;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int order = 1;  // Discrete: rotations by 2 pi k / order about the axis
  // Rotations of the set (a continuous symmetry is sampled every `step_deg`).
  std::vector<Eigen::Matrix3d> rotations(double step_deg = 1.0) const;
  std::string describe() const;
};
// "none" | "discrete N x|y|z" | "continuous x|y|z"; throws laserfit::Error otherwise.
Symmetry parse_symmetry(const std::string& text);

struct PoseError {
  double t_mm = 0;     // translation of the object frame's origin
  double r_deg = 0;    // rotation angle (for a continuous symmetry: angle between the axes)
  double mssd_mm = 0;  // max over the model points of |T_est x - T_gt S x|, min over S
};

// Error of `est` against `gt` (both T_scan_object), minimised over the symmetries. `model`:
// points of the object (object frame) for MSSD; empty -> mssd_mm = 0.
PoseError pose_error(const Pose& est, const Pose& gt, const Symmetry& sym,
                     const std::vector<Eigen::Vector3f>& model = {});

}  // namespace laserfit::metrics
