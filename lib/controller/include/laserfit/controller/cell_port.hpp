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
#include "laserfit/robot/motion.hpp"

namespace laserfit::controller {

// A Cartesian motion of the assembling arm: the flange to `T_baseA_flange_goal` (A's base frame,
// mm) along a straight minimum-jerk path, the elbow pulled toward `q_ref` in the null space.
struct MotionCommand {
  Pose T_baseA_flange_goal = Pose::Identity();
  robot::Joints q_ref = robot::Joints::Zero();
  robot::MotionSettings motion;
};

struct MotionReport {
  bool ok = false;
  std::string reason;                       // why not (a fault reported by the arm)
  robot::Joints q = robot::Joints::Zero();  // the joints the arm reports at the end
  double duration_s = 0;                    // the motion's duration, settling included
};

// A sweep of the sensing arm. sweep_mm > the scene's sweep: a longer sweep about the same centre
// (a search scan); raised: from the search pose farther back along the view axis.
struct ScanRequest {
  double sweep_mm = 0;
  bool raised = false;
};

// What a sweep returns: the cloud (an empty one: no data) and how long the sweep took (s).
struct Sweep {
  PointCloud cloud;
  double duration_s = 0;
};

class CellPort {
 public:
  virtual ~CellPort() = default;
  virtual robot::Joints joints() = 0;  // the assembling arm's joints now
  virtual MotionReport move(const MotionCommand& command) = 0;
  virtual Sweep scan(const ScanRequest& request) = 0;
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
