// Ridge regression of the arm's local move error: A = E D^T (D D^T + r^2 I)^-1 over the moves
// commanded (columns of D) and their measured landing errors (columns of E).
#include "laserfit/controller/motion_error.hpp"

#include <Eigen/Dense>

namespace laserfit::controller {

bool MotionErrorModel::observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& error) {
  if (!s_.enabled || !commanded.allFinite() || !error.allFinite()) return false;
  if (error.norm() > s_.max_gain * commanded.norm()) return false;
  DDt_ += commanded * commanded.transpose(), EDt_ += error * commanded.transpose(), ++n_;
  const double r2 = s_.ridge_mm * s_.ridge_mm;
  Eigen::Matrix3d A = EDt_ * (DDt_ + r2 * Eigen::Matrix3d::Identity()).inverse();
  const double norm = Eigen::JacobiSVD<Eigen::Matrix3d>(A).singularValues()[0];
  if (norm > s_.max_gain) A *= s_.max_gain / norm;
  A_ = A;
  return true;
}

Eigen::Vector3d MotionErrorModel::command_for(const Eigen::Vector3d& wanted) const {
  if (!s_.enabled || n_ == 0) return wanted;
  return (Eigen::Matrix3d::Identity() + A_).partialPivLu().solve(wanted);
}

}  // namespace laserfit::controller
