#pragma once
// What the executed moves teach about the assembling arm near the insertion pose. A move of the
// part commanded as c (mm) lands at c + A c: on small moves an arm whose model is off acts
// linearly, A = J_true J_nominal^-1 - I (a few per cent for millimetre length and ~10 mrad angle
// errors of its links), plus its repeatability, which no model removes. Each move is measured by
// the next scan (the part relative to the target, before and after), so A is estimated from the
// moves made so far, and the next move is commanded as (I + A)^-1 of the one wanted.
#include <Eigen/Core>

namespace laserfit::controller {

struct MotionLearningSettings {
  bool enabled = true;
  // Ridge of the estimate (mm): along a direction the moves so far travelled d, the estimate is
  // shrunk by d^2 / (d^2 + ridge^2), so the repeatability of a short move (~12 um for 0.6 mm)
  // is not taken for a model error.
  double ridge_mm = 0.5;
  // A move that landed farther off than this fraction of it was mismeasured, not moved by a
  // model error: it is not learned from; |A| (spectral norm) is held to it too.
  double max_gain = 0.3;
};

class MotionErrorModel {
 public:
  explicit MotionErrorModel(const MotionLearningSettings& s = {}) : s_(s) {}
  // A move commanded as `commanded` whose landing was measured `error` away from it (mm); false
  // when it is not learned from (learning off, or a mismeasured move).
  bool observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& error);
  // The command that lands the wanted move, by what has been learned (the wanted move itself
  // before any observation or with learning off).
  Eigen::Vector3d command_for(const Eigen::Vector3d& wanted) const;
  const Eigen::Matrix3d& gain() const { return A_; }
  int observations() const { return n_; }

 private:
  MotionLearningSettings s_;
  Eigen::Matrix3d DDt_ = Eigen::Matrix3d::Zero(), EDt_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d A_ = Eigen::Matrix3d::Zero();
  int n_ = 0;
};

}  // namespace laserfit::controller
