// The checks on what crosses the port: every request a cell acts on and every report the loop
// acts on, so that a peer that lies is one line, never a motion.
#include <cmath>
#include <sstream>

#include "laserfit/controller/cell_port.hpp"

namespace laserfit::controller {
namespace {

constexpr double kMaxSweep_mm = 1000, kMaxSpeed_mm_s = 500;  // a line scan, not a transfer
constexpr double kMaxMotion_s = 120;                         // one motion, settling included
constexpr size_t kMaxProfiles = 100000;

std::string joints_problem(const robot::Joints& q, const robot::JointLimits& l) {
  for (int j = 0; j < 7; ++j) {
    if (!std::isfinite(q[j])) return "joint " + std::to_string(j + 1) + " is not a number";
    if (q[j] < l.q_min[j] || q[j] > l.q_max[j]) {
      std::ostringstream o;
      o << "joint " << j + 1 << " at " << q[j] << " rad is outside [" << l.q_min[j] << ", "
        << l.q_max[j] << "]";
      return o.str();
    }
  }
  return "";
}

}  // namespace

std::string check_request(const SweepRequest& r, const robot::JointLimits& limits) {
  if (const std::string p = joints_problem(r.q_start, limits); !p.empty())
    return "sweep start: " + p;
  if (!r.direction.allFinite() || std::abs(r.direction.norm() - 1) > 1e-6)
    return "sweep direction is not a unit vector";
  if (!(r.length_mm > 0 && r.length_mm <= kMaxSweep_mm))
    return "sweep length " + std::to_string(r.length_mm) + " mm is outside (0, 1000]";
  if (!(std::abs(r.lead_mm) <= kMaxSweep_mm)) return "sweep lead is outside [-1000, 1000] mm";
  if (!(r.speed_mm_s > 0 && r.speed_mm_s <= kMaxSpeed_mm_s))
    return "sweep speed " + std::to_string(r.speed_mm_s) + " mm/s is outside (0, 500]";
  return "";
}

// The path must be one the arm's Cartesian controller accepts: finite, unit rotations, at a
// sane rate, and no faster between samples than the flange's velocity limits.
std::string check_request(const MotionCommand& m, const robot::ArmModel& arm) {
  const auto& p = m.path;
  if (!(p.rate_hz >= 100 && p.rate_hz <= 10000))
    return "path rate " + std::to_string(p.rate_hz) + " Hz is outside [100, 10000]";
  if (p.size() == 0 || p.q.size() != p.size()) return "the path has no samples";
  if (p.duration_s() > kMaxMotion_s) return "the path is longer than 120 s";
  for (size_t i = 0; i < p.size(); ++i) {
    if (!p.t[i].allFinite() || !p.q[i].coeffs().allFinite() || std::abs(p.q[i].norm() - 1) > 1e-9)
      return "path sample " + std::to_string(i) + " is not a pose";
    if (i == 0) continue;
    const double v = (p.t[i] - p.t[i - 1]).norm() * p.rate_hz;
    const double w = p.q[i].angularDistance(p.q[i - 1]) * p.rate_hz;
    if (v > arm.cartesian.v_mm_s || w > arm.cartesian.w_rad_s)
      return "path sample " + std::to_string(i) + " exceeds the flange's velocity limits";
  }
  if (const std::string q = joints_problem(m.q_ref, arm.limits); !q.empty())
    return "elbow reference: " + q;
  return "";
}

std::string check_report(const Sweep& s, int points_per_profile) {
  const auto& p = s.profiles;
  if (p.count == 0) return "";  // no data: the loop's own stop, not a malformed report
  if (p.width != points_per_profile)
    return std::to_string(p.width) + " points per profile, the scanner has " +
           std::to_string(points_per_profile);
  if (size_t(p.count) > kMaxProfiles) return "more than 100000 profiles";
  if (p.xz.size() != size_t(p.width) * size_t(p.count))
    return "the profiles' point count is not width x count";
  if (s.T_world_flange.size() != size_t(p.count)) return "not one flange pose per profile";
  for (const Pose& T : s.T_world_flange)
    if (!T.matrix().allFinite()) return "a flange pose is not a number";
  for (const auto& q : p.xz)  // NaN is "no measurement"; infinities and absurd values lie
    if (std::isinf(q.x()) || std::isinf(q.y()) || std::abs(q.x()) > 1e4 || std::abs(q.y()) > 1e4)
      return "a profile point is out of range";
  if (!(s.duration_s >= 0 && s.duration_s < 3600)) return "the sweep's duration is out of range";
  return "";
}

std::string check_report(const MotionReport& m, const robot::JointLimits& limits) {
  if (!m.ok) return "";  // a fault: its reason is the report
  if (const std::string q = joints_problem(m.q, limits); !q.empty()) return "reported " + q;
  if (!(m.duration_s >= 0 && m.duration_s < 3600)) return "the motion's duration is out of range";
  return "";
}

}  // namespace laserfit::controller
