#include "laserfit/robot/error_model.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"

namespace laserfit::robot {

void ErrorModelSettings::validate() const {
  if (!(length_min_mm >= 0 && length_max_mm >= length_min_mm && length_max_mm < 100))
    throw Error("error model: link length errors need 0 <= min <= max < 100 mm");
  if (!(angle_min_mrad >= 0 && angle_max_mrad >= angle_min_mrad && angle_max_mrad < 200))
    throw Error("error model: angle errors need 0 <= min <= max < 200 mrad");
  if (!(repeatability_mm >= 0 && repeatability_mm < 10 && repeatability_mrad >= 0 &&
        repeatability_mrad < 100))
    throw Error("error model: repeatability must be in 0..10 mm and 0..100 mrad");
  if (!(repeatability_corr_mm >= 0 && repeatability_corr_mm < 1000))
    throw Error("error model: repeatability correlation length must be in 0..1000 mm");
}

ArmModel perturbed_arm(const ArmModel& nominal, const ErrorModelSettings& s, uint64_t seed) {
  s.validate();
  Mt19937_64 g = block_rng(seed, 0xA4A, 0);
  auto signed_in = [&](double lo, double hi) {
    const double m = lo + (hi - lo) * uniform01(g);
    return uniform01(g) < 0.5 ? -m : m;
  };
  ArmModel t = nominal;
  t.name = nominal.name + " (perturbed, seed " + std::to_string(seed) + ")";
  auto perturb = [&](DhRow& r) {
    r.a_mm += signed_in(s.length_min_mm, s.length_max_mm);
    r.d_mm += signed_in(s.length_min_mm, s.length_max_mm);
    r.alpha_rad += 1e-3 * signed_in(s.angle_min_mrad, s.angle_max_mrad);
    r.theta_rad += 1e-3 * signed_in(s.angle_min_mrad, s.angle_max_mrad);
  };
  for (auto& r : t.joints) perturb(r);
  perturb(t.flange);
  return t;
}

namespace {
Pose small_motion(const Eigen::Matrix<double, 6, 1>& e, const ErrorModelSettings& s) {
  Pose d = Pose::Identity();
  d.translation() = e.head<3>() * s.repeatability_mm;
  const Eigen::Vector3d r = e.tail<3>() * (s.repeatability_mrad * 1e-3);
  if (r.norm() > 0) d.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  return d;
}
}  // namespace

Pose Repeatability::reach(const Pose& T, Mt19937_64& g) {
  Eigen::Matrix<double, 6, 1> fresh;
  for (int i = 0; i < 6; ++i) fresh[i] = gauss(g);
  const double d = started_ ? (T.translation() - last_).norm() : 1e300;
  const double rho = s_.repeatability_corr_mm > 0 ? std::exp(-d / s_.repeatability_corr_mm) : 0.0;
  e_ = rho * e_ + std::sqrt(1 - rho * rho) * fresh;
  last_ = T.translation(), started_ = true;
  return T * small_motion(e_, s_);
}

Pose with_repeatability(const Pose& T, const ErrorModelSettings& s, Mt19937_64& g) {
  // One draw per statement: the order of a constructor's arguments is unspecified, and the
  // same seed must give the same arm with any compiler (this is GCC's order, as recorded).
  Eigen::Vector3d dt, dr;
  for (int i = 2; i >= 0; --i) dt[i] = gauss(g);
  for (int i = 2; i >= 0; --i) dr[i] = gauss(g);
  Pose d = Pose::Identity();
  d.translation() = dt * s.repeatability_mm;
  const Eigen::Vector3d r = dr * (s.repeatability_mrad * 1e-3);
  if (r.norm() > 0) d.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  return T * d;
}

}  // namespace laserfit::robot
