#include "laserfit/planning/correction.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "laserfit/core/error.hpp"

namespace laserfit::planning {
namespace {

// Minimum-jerk profile and its peak derivatives for a unit move over unit time.
double s_of(double x) { return x * x * x * (10 + x * (-15 + 6 * x)); }
constexpr double kPeakV = 1.875, kPeakA = 5.773502691896258, kPeakJ = 60.0;

// Shortest duration whose peak velocity / acceleration / jerk stay within the limits for a move
// of `d` (mm or rad).
double duration_for(double d, double v, double a, double j) {
  if (d <= 0) return 0;
  return std::max({kPeakV * d / v, std::sqrt(kPeakA * d / a), std::cbrt(kPeakJ * d / j)});
}

// Peak magnitudes of the first three finite differences of a sampled vector signal.
std::array<double, 3> peaks(const std::vector<Eigen::Vector3d>& x, double dt) {
  std::array<double, 3> p = {0, 0, 0};
  for (size_t i = 1; i < x.size(); ++i) p[0] = std::max(p[0], (x[i] - x[i - 1]).norm() / dt);
  for (size_t i = 2; i < x.size(); ++i)
    p[1] = std::max(p[1], (x[i] - 2 * x[i - 1] + x[i - 2]).norm() / (dt * dt));
  for (size_t i = 3; i < x.size(); ++i)
    p[2] = std::max(p[2], (x[i] - 3 * x[i - 1] + 3 * x[i - 2] - x[i - 3]).norm() / (dt * dt * dt));
  return p;
}

}  // namespace

void CorrectionSettings::validate() const {
  if (!(max_translation_mm > 0 && max_rotation_deg > 0 && rate_hz >= 10 && rate_hz <= 100000 &&
        speed_fraction > 0 && speed_fraction <= 1 && min_duration_s >= 0))
    throw Error(
        "correction settings: amplitudes > 0, rate 10..100000 Hz, speed fraction in (0, 1]");
}

Trajectory check_correction(const Pose& A, const Pose& B, const CorrectionSettings& s) {
  s.validate();
  Trajectory tr;
  const Eigen::AngleAxisd dR(A.linear().transpose() * B.linear());  // rotation in the start frame
  tr.translation_mm = (B.translation() - A.translation()).norm();
  tr.rotation_deg = dR.angle() * 180 / M_PI;
  if (!A.matrix().allFinite() || !B.matrix().allFinite()) {
    tr.reason = "non-finite start or goal pose";
  } else if (tr.translation_mm > s.max_translation_mm || tr.rotation_deg > s.max_rotation_deg) {
    std::ostringstream m;
    m << "correction of " << tr.translation_mm << " mm / " << tr.rotation_deg
      << " deg exceeds the limit of " << s.max_translation_mm << " mm / " << s.max_rotation_deg
      << " deg";
    tr.reason = m.str();
  }
  return tr;
}

Trajectory plan_correction(const Pose& A, const Pose& B, const CorrectionSettings& s) {
  Trajectory tr = check_correction(A, B, s);
  if (!tr.reason.empty()) return tr;
  const Eigen::Vector3d dp = B.translation() - A.translation();
  const Eigen::AngleAxisd dR(A.linear().transpose() * B.linear());  // rotation in the start frame
  const auto& L = s.limits;
  const double f = s.speed_fraction;
  double T = std::max({duration_for(tr.translation_mm, f * L.v_mm_s, f * L.a_mm_s2, f * L.j_mm_s3),
                       duration_for(dR.angle(), f * L.w_rad_s, f * L.dw_rad_s2, f * L.ddw_rad_s3),
                       s.min_duration_s});
  const double dt = 1.0 / s.rate_hz;
  const int n = std::max(2, int(std::ceil(T / dt)));
  T = n * dt;  // whole samples; a longer duration only lowers the peaks
  tr.duration_s = T;
  const Eigen::Quaterniond qa(A.linear()), qb(B.linear());
  std::vector<Eigen::Vector3d> pos, rot;
  for (int i = 0; i <= n; ++i) {
    const double u = s_of(double(i) / n);
    Pose P = Pose::Identity();
    P.translation() = A.translation() + u * dp;
    P.linear() = qa.slerp(u, qb).toRotationMatrix();
    tr.samples.push_back({i * dt, P});
    pos.push_back(P.translation());
    rot.push_back(dR.axis() * (u * dR.angle()));  // angle along the geodesic (fixed axis)
  }
  const auto pp = peaks(pos, dt), pr = peaks(rot, dt);
  tr.peak_v_mm_s = pp[0], tr.peak_a_mm_s2 = pp[1], tr.peak_j_mm_s3 = pp[2];
  tr.peak_w_rad_s = pr[0], tr.peak_dw_rad_s2 = pr[1], tr.peak_ddw_rad_s3 = pr[2];
  // The plan is checked on its own samples, not trusted from the formula.
  const bool within = pp[0] <= L.v_mm_s && pp[1] <= L.a_mm_s2 && pp[2] <= L.j_mm_s3 &&
                      pr[0] <= L.w_rad_s && pr[1] <= L.dw_rad_s2 && pr[2] <= L.ddw_rad_s3;
  if (!within) {
    tr.samples.clear();
    tr.reason = "sampled trajectory exceeds the Cartesian limits";
    return tr;
  }
  tr.ok = true;
  return tr;
}

}  // namespace laserfit::planning
