#pragma once
// What the on-line loop needs from a cell, real or simulated: the assembling arm moves to a
// Cartesian goal under its own controller and reports its joints; the sensing arm sweeps and the
// scanner's profiles come back as one cloud in the frame the sensing arm believes (world); a stop.
// The loop plans, measures and decides from what the cell reports and the cell's nominal model
// (cell::Cell's believed parts); everything true about the cell stays behind this interface.
#include <optional>
#include <string>

#include "laserfit/cell/cell.hpp"
#include "laserfit/core/cloud.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/profiles.hpp"
#include "laserfit/robot/motion.hpp"

namespace laserfit::controller {

// A Cartesian motion of the assembling arm: the flange along `path` (A's base frame, mm, sampled
// at the arm controller's rate; the loop plans it from the flange pose the arm reports), the elbow
// pulled toward `q_ref` in the null space (the paper's IC1 / IC2 bias). Guarded: where the part
// meets resistance the arm stops and reports the contact (a descent toward a target whose distance
// the scans could not fix); unguarded, a contact is a fault (the collision reflex).
struct MotionCommand {
  robot::CartesianPath path;
  robot::Joints q_ref = robot::Joints::Zero();
  bool guarded = false;
};

struct MotionReport {
  bool ok = false;
  std::string reason;                       // why not (a fault reported by the arm)
  robot::Joints q = robot::Joints::Zero();  // the joints the arm reports at the end
  double duration_s = 0;                    // the motion's duration, settling included
  bool contact = false;                     // a guarded motion stopped at a contact (ok)
};

// A sweep of the sensing arm: to the joints `q_start` (its taught scan pose), back `lead_mm`
// along `direction`, then `length_mm` along it at `speed_mm_s` while the scanner records.
struct SweepRequest {
  robot::Joints q_start = robot::Joints::Zero();  // rad
  Eigen::Vector3d direction = {0, 1, 0};          // sensor frame, unit
  double lead_mm = 0, length_mm = 0, speed_mm_s = 0;
};

// What a sweep returns: the scanner's profiles (sensor frame: x along the line, z the depth, mm,
// NaN = no measurement) and the flange pose the sensing arm reports for each (its base = the
// world frame), and how long the sweep took (s). No profile: no data.
struct Sweep {
  std::string fault;  // why the cell could not sweep ("" when it did)
  io::Profiles profiles;
  std::vector<Pose> T_world_flange;
  double duration_s = 0;
};

// What is wrong with a request or a report, "" when nothing: checked before a cell acts on a
// request and before the loop acts on a report (lengths mm, the sensing arm's limits).
std::string check_request(const SweepRequest& r, const robot::JointLimits& limits);
std::string check_request(const MotionCommand& m, const robot::ArmModel& arm);
std::string check_report(const Sweep& s, int points_per_profile);
std::string check_report(const MotionReport& m, const robot::JointLimits& limits);

// What a cell's call throws when the cell failed on it (a lost peer, a timeout, a malformed
// reply): the loop ends the trial as a cell fault. Any other laserfit::Error is the loop's own
// refusal.
struct CellFailure : Error {
  using Error::Error;
};

class CellPort {
 public:
  virtual ~CellPort() = default;
  virtual robot::Joints joints() = 0;  // the assembling arm's joints now
  virtual MotionReport move(const MotionCommand& command) = 0;
  virtual Sweep scan(const SweepRequest& request) = 0;
  virtual void stop() = 0;
  // What only a simulated cell knows (the insertion judged on the true poses, the true error):
  // a real cell answers nothing.
  virtual std::optional<cell::Insertion> judge() { return std::nullopt; }
  // The part's true error from a goal (target frame): lateral and along its axis (mm).
  virtual std::optional<Eigen::Vector2d> true_error(const Pose& /*T_target_part_goal*/) {
    return std::nullopt;
  }
};

}  // namespace laserfit::controller
