#pragma once
// The "true" robot of a simulation: the nominal model with seeded errors in its kinematic
// parameters (as identified on real Pandas: link lengths 0.5-5 mm, angles 2-25 mrad), plus
// repeatability noise on every reached pose. Its pose error therefore depends on the joint
// configuration: a pose taught in one configuration (IC1) is reproduced to the repeatability,
// the same pose reached with another elbow (IC2) is off by millimetres.
#include <cstdint>
#include "laserfit/core/rng.hpp"

#include "laserfit/robot/arm.hpp"

namespace laserfit::robot {

struct ErrorModelSettings {
  double length_min_mm = 0.5,
         length_max_mm = 5.0;  // |error| of every a and d, uniform, random sign
  double angle_min_mrad = 2.0, angle_max_mrad = 25.0;  // |error| of every alpha and joint offset
  double repeatability_mm = 0.1;                       // per reached pose: isotropic, std per axis
  double repeatability_mrad = 0.1;                     //   and the same for orientation
  double repeatability_corr_mm = 20.0;  // the error of two poses this close is correlated
                                        // (exp(-distance / this)): a small move keeps it
  void validate() const;                // throws laserfit::Error on nonsense
};

// The true arm: nominal parameters plus errors drawn from `seed` (deterministic).
ArmModel perturbed_arm(const ArmModel& nominal, const ErrorModelSettings& s, uint64_t seed);

// A reached pose with repeatability noise: T * small random motion in the flange frame.
Pose with_repeatability(const Pose& T, const ErrorModelSettings& s, Mt19937_64& g);

// Repeatability along a sequence of reached poses: the error is an AR(1) process over the path
// length (friction and elasticity that settle the same way after a small move), fresh after a
// long one. One per arm and trial.
class Repeatability {
 public:
  explicit Repeatability(const ErrorModelSettings& s) : s_(s) {}
  Pose reach(const Pose& T_base_flange_true, Mt19937_64& g);

 private:
  ErrorModelSettings s_;
  Eigen::Matrix<double, 6, 1> e_ = Eigen::Matrix<double, 6, 1>::Zero();  // standard-normal state
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
  bool started_ = false;
};

}  // namespace laserfit::robot
