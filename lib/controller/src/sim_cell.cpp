// The simulated cell behind the controller's port (see sim.hpp).
#include <algorithm>

#include "laserfit/controller/sim.hpp"
#include "laserfit/core/rng.hpp"

namespace laserfit::controller {

uint64_t scan_seed(uint64_t trial_seed, int n) {
  return mix_seed(trial_seed ^ (uint64_t(n) << 32));
}

SimCell::SimCell(const cell::Cell& c, const SimSetup& su, int start, uint64_t seed)
    : c_(c),
      su_(su),
      seed_(seed),
      g_(block_rng(seed, 0xC0, 0)),
      rep_(c.s.arm_errors),
      q_(su.q_start.at(start)) {}

// The arm's own Cartesian controller runs on its nominal model (all a real controller knows);
// where the part truly lands follows from the true arm at the joints it ends in.
MotionReport SimCell::move(const MotionCommand& command) {
  const robot::MotionResult r = robot::move_cartesian(c_.nominal, q_, command.T_baseA_flange_goal,
                                                      command.q_ref, command.motion);
  q_ = r.q;
  part_ = c_.part_true(q_, rep_, g_);
  MotionReport out;
  out.ok = true, out.q = q_, out.duration_s = r.duration_s;
  return out;
}

// The sweep takes its length at the sweep speed (the sensing arm's move to the raised pose and
// back is not counted).
Sweep SimCell::scan(const ScanRequest& request) {
  const Pose part = part_ ? *part_ : c_.part_believed(q_);
  const auto& sw = c_.s.scene.settings.sweep;
  Sweep out;
  out.cloud =
      scan_cell(c_, su_, part, scan_seed(seed_, scans_++), g_, request.sweep_mm, request.raised);
  out.duration_s = std::max(request.sweep_mm, sw.length_mm) / sw.speed_mm_s;
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
