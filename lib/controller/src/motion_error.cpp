// Ridge regression of the arm's local move error: A = E D^T (D D^T + r^2 I)^-1 over the moves
// commanded (columns of D: the move and the turn times the lever) and their measured landing
// errors (columns of E).
#include "laserfit/controller/motion_error.hpp"

#include <Eigen/Dense>

namespace laserfit::controller {

bool MotionErrorModel::observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& turned,
                               const Eigen::Vector3d& error) {
  Eigen::Matrix<double, 6, 1> d;
  d << commanded, s_.lever_mm * turned;
  if (!s_.enabled || !d.allFinite() || !error.allFinite()) return false;
  if (error.norm() > s_.max_gain * d.norm()) return false;
  DDt_ += d * d.transpose(), EDt_ += error * d.transpose(), ++n_;
  const double r2 = s_.ridge_mm * s_.ridge_mm;
  Gain A = EDt_ * (DDt_ + r2 * Eigen::Matrix<double, 6, 6>::Identity()).inverse();
  const double norm = Eigen::JacobiSVD<Gain>(A).singularValues()[0];
  if (norm > s_.max_gain) A *= s_.max_gain / norm;
  A_ = A;
  return true;
}

// The part lands at c + A_move c + A_turn (L w): solve for c.
Eigen::Vector3d MotionErrorModel::command_for(const Eigen::Vector3d& wanted,
                                              const Eigen::Vector3d& turned) const {
  if (!s_.enabled || n_ == 0) return wanted;
  const Eigen::Matrix3d I_A = Eigen::Matrix3d::Identity() + A_.leftCols<3>();
  return I_A.partialPivLu().solve(wanted - A_.rightCols<3>() * (s_.lever_mm * turned));
}

}  // namespace laserfit::controller
