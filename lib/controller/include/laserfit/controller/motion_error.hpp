#pragma once
// What the executed moves teach about the assembling arm near the insertion pose. On small moves
// an arm whose model is off acts linearly: its flange twist lands at (I + J_true J_nominal^-1 - I)
// of the one commanded (a few per cent for millimetre length and ~10 mrad angle errors of its
// links), plus its repeatability, which no model removes. A part held at a lever from the wrist
// therefore lands off by A [c; L w]: c its commanded move (mm), w its commanded turn (rad, as a
// rotation vector), L the lever that puts a turn in millimetres. A turn's error is the larger
// one (1 deg at 10 % moves a part 100 mm out by 0.17 mm), so a model of c alone takes it for a
// translation error and extrapolates it. Each move is measured by the next scan (the part
// relative to the target, before and after), A is estimated from the moves made so far, and the
// next move is commanded so that it lands where wanted.
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
  // A turn of w rad counts as w * lever_mm of motion: about the part's distance from the wrist.
  double lever_mm = 100;
};

class MotionErrorModel {
 public:
  explicit MotionErrorModel(const MotionLearningSettings& s = {}) : s_(s) {}
  using Gain = Eigen::Matrix<double, 3, 6>;
  // A move commanded as `commanded` (mm) with a turn `turned` (rad) whose landing was measured
  // `error` away from it (mm); false when it is not learned from (learning off, or a mismeasured
  // move).
  bool observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& turned,
               const Eigen::Vector3d& error);
  bool observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& error) {
    return observe(commanded, Eigen::Vector3d::Zero(), error);
  }
  // The move to command so that, turning by `turned`, the part lands the wanted move, by what has
  // been learned (the wanted move itself before any observation or with learning off).
  Eigen::Vector3d command_for(const Eigen::Vector3d& wanted,
                              const Eigen::Vector3d& turned = Eigen::Vector3d::Zero()) const;
  const Gain& gain() const { return A_; }
  int observations() const { return n_; }

 private:
  MotionLearningSettings s_;
  Eigen::Matrix<double, 6, 6> DDt_ = Eigen::Matrix<double, 6, 6>::Zero();
  Gain EDt_ = Gain::Zero(), A_ = Gain::Zero();
  int n_ = 0;
};

}  // namespace laserfit::controller
