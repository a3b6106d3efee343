// The simulated cell behind the controller's port (see sim.hpp).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "laserfit/controller/sim.hpp"
#include "laserfit/core/rng.hpp"

namespace laserfit::controller {

namespace {
// The path up to where the flange has covered `fraction` of its way to the goal (a stop there).
robot::CartesianPath cut_at(const robot::CartesianPath& path, double fraction) {
  robot::CartesianPath out = path;
  if (path.size() < 2) return out;
  const double total = (path.t.back() - path.t.front()).norm();
  size_t n = 1;
  while (n < path.size() && (path.t[n - 1] - path.t.front()).norm() < fraction * total) ++n;
  out.t.resize(n), out.q.resize(n);
  return out;
}
}  // namespace

uint64_t scan_seed(uint64_t trial_seed, int n) {
  return mix_seed(trial_seed ^ (uint64_t(n) << 32));
}

SimCell::SimCell(const cell::Cell& c, const SimSetup& su, int start, uint64_t seed,
                 const robot::MotionSettings& arm)
    : c_(c),
      su_(su),
      seed_(seed),
      arm_(arm),
      g_(block_rng(seed, 0xC0, 0)),
      rep_(c.s.arm_errors),
      q_(su.q_start.at(start)) {}

// The arm's own Cartesian controller runs on its nominal model (all a real controller knows);
// where the part truly lands follows from the true arm at the joints it ends in. A path it would
// not accept, a joint limit met on the way, or the part running into the target unguarded (the
// Panda's reflexes) is a fault; guarded, the arm stops at the contact and reports it.
MotionReport SimCell::move(const MotionCommand& command) {
  MotionReport out;
  if (out.reason = check_request(command, c_.nominal); !out.reason.empty()) return out;
  // Where the part starts: where the last motion left it, else the true arm at its start joints.
  const Pose from =
      part_ ? *part_ : c_.T_world_baseA_true * c_.trueA.fk(q_) * c_.T_flange_part_true;
  const robot::Joints q0 = q_;
  const robot::MotionResult r =
      robot::follow_cartesian(c_.nominal, q_, command.path, command.q_ref, arm_);
  q_ = r.q;
  part_ = c_.part_true(q_, rep_, g_);
  out.q = q_, out.duration_s = r.duration_s;
  if (!r.limits_ok) return out.reason = "joint position limit reached", out;
  // The true path is the commanded line bent by the arm's model error, which varies slowly along
  // it: the straight line between the true end poses stands for it. In the hole, the walls
  // hold the part within its clearance however the arm drifts.
  bool entered = false;
  const auto hit = cell::first_contact(c_.s, su_.T_world_target, from, *part_, 0.1, &entered);
  if (entered) part_ = cell::guided(c_.s, su_.T_world_target, *part_);
  if (hit && command.guarded) {
    // Stopped where the true arm first carries the part into the face: the path cut there, found
    // by bisection on the fraction of the path followed (the line above only says that it does).
    auto blocked = [&](double f, robot::Joints& q) {
      q = robot::follow_cartesian(c_.nominal, q0, cut_at(command.path, f), command.q_ref, arm_).q;
      const Pose p = c_.T_world_baseA_true * c_.trueA.fk(q) * c_.T_flange_part_true;
      return cell::first_contact(c_.s, su_.T_world_target, from, p).has_value();
    };
    double lo = 0, hi = 1;
    robot::Joints q = q0, probe;
    for (int i = 0; i < 16; ++i) {
      const double f = (lo + hi) / 2;
      if (blocked(f, probe))
        hi = f;
      else
        lo = f, q = probe;
    }
    q_ = q, part_ = c_.part_true(q_, rep_, g_);
    out.q = q_, out.duration_s = lo * r.duration_s, out.contact = true;
  } else if (hit) {
    part_ = hit->T_world_part;  // stopped there (the joints reported are the goal's)
    std::ostringstream why;
    why.precision(3);
    why << "collision: the part ran into the target " << hit->travelled_mm
        << " mm along the motion, its axis " << std::hypot(hit->at.x_mm, hit->at.y_mm)
        << " mm from the hole's centre (collision reflex)";
    return out.reason = why.str(), out;
  }
  out.ok = true;
  return out;
}

// The sweep takes its length at its speed (the sensing arm's move to its start and back is not
// counted). The profiles are the simulator's in the sensor frame, each with the flange pose the
// sensing arm believes (nominal kinematics, the believed hand-eye calibration).
Sweep SimCell::scan(const SweepRequest& request) {
  Sweep out;
  if (out.fault = check_request(request, c_.nominal.limits); !out.fault.empty()) return out;
  const Pose part = part_ ? *part_ : c_.part_believed(q_);
  const scan::ScanResult r = sweep_cell(c_, su_, part, scan_seed(seed_, scans_++), g_, request);
  out.duration_s = request.length_mm / request.speed_mm_s;
  out.profiles.width = int(r.raw.width), out.profiles.count = int(r.raw.height);
  out.profiles.xz.reserve(r.raw.points.size());
  for (const auto& p : r.raw.points) out.profiles.xz.emplace_back(p.x(), p.z());
  const Pose T_sensor_flange = c_.s.T_flange_sensor.inverse();
  for (const Pose& T : r.T_base_sensor_nominal) out.T_world_flange.push_back(T * T_sensor_flange);
  return out;
}

std::optional<cell::Insertion> SimCell::judge() {
  if (!part_) return std::nullopt;
  return cell::check_insertion(c_.s, su_.T_world_target, *part_);
}

std::optional<Eigen::Vector2d> SimCell::true_error(const Pose& T_target_part_goal) {
  if (!part_) return std::nullopt;
  const Pose goal = su_.T_world_target * T_target_part_goal;
  const Eigen::Vector3d e = goal.translation() - part_->translation(), n = goal.linear().col(2);
  return Eigen::Vector2d((e - n * n.dot(e)).norm(), n.dot(e));
}

}  // namespace laserfit::controller
