#pragma once
// The on-line controller (the paper's Section III-C and IV): reach the insertion pose with
// proprioception only (IC1 / IC2), or approach, scan, register the target and the part, correct
// the relative error with a short planned trajectory, verify by re-scanning, insert. Every
// decision is logged; an `ambiguous` registration is used only when its unobservable DoF is one
// the task declares harmless, a `failed` one triggers a re-scan (bounded), and a correction above
// the amplitude limit is refused, never executed.
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "laserfit/cell/cell.hpp"
#include "laserfit/controller/motion_error.hpp"
#include "laserfit/core/cloud.hpp"
#include "laserfit/core/enum_names.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/planning/correction.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/registration/thresholds.hpp"
#include "laserfit/robot/motion.hpp"

namespace laserfit::controller {

enum class Strategy { ProprioIC1, ProprioIC2, Laser, LaserPose };  // names: EnumNames below

struct ControllerSettings {
  registration::Thresholds thresholds;  // from laserfit tune (validated by its loader)
  planning::CorrectionSettings correction;
  robot::MotionSettings motion;
  int max_scans = 3;              // scans per measurement (re-scan on a rejected registration)
  int max_rounds = 3;             // correction rounds, each verified by a new scan
  double verify_mm = 0.02;        // measured lateral residual that ends the rounds
  double verify_axial_mm = 0.05;  //   and along the insertion axis (a tip is measured to
                                  //   about one 10 um profile step)
  double axial_gate_mm = 0.3;     // after the approach's corrections, one stage move cannot
                                  // leave the part farther than this along its axis (it
                                  // lands within ~0.15 mm): a larger reading is re-scanned,
                                  // and the part moves at most this far per round along it
  // Scan only where it pays: a correction is applied together with the move to the next
  // waypoint, whose scan verifies both, while that waypoint is still outside the target or the
  // correction is small enough that its own error (a move of d mm lands up to ~0.1 d off) stays
  // within a quarter of the cell's smallest lateral clearance: fold_max_mm, or when 0, 2.5x that
  // clearance (needle 0.21 mm, USB 0.125 mm). Otherwise, and with fold off (the paper's loop),
  // each correction is verified by a scan of its own.
  bool fold = true;
  double fold_max_mm = 0;
  // The laser strategies' moves are guarded: a part that meets the target's face stops there,
  // which fixes its position along the axis where no scan could (a plug seen from behind); the
  // loop backs off and goes on from the first stage. More contacts than this: refused.
  int max_touches = 2;
  MotionLearningSettings learning;  // each move measured by the next scan corrects the next one
  size_t reference_points = 60000;
  double prior_radius_mm = 1.0;  // scan points this near a prior-placed reference are a
                                 // candidate part (else the clusters nearest the prior)
  std::string dump_dir;          // non-empty: write every scan and the references here
  // A flange pose handed in from outside (`correct --ee-pose`) is trusted only if the scan finds
  // the part within this of where the pose puts it. The simulated arms' kinematic errors leave
  // the part up to ~50 mm from its believed pose (46 mm in test_correct), so only a gross
  // mistake is caught: a pose in metres read as mm, another frame, another arm's pose.
  double max_part_offset_mm = 100;
  // A target trusted earlier in the trial and now `ambiguous` about one rotation only (the part
  // in front of it hides what pinned that turn) keeps that turn from its last trusted
  // measurement, if this scan puts it within these of that measurement: the target has not
  // moved and the sensing arm repeats its scan pose to ~0.1 mm.
  double tracked_target_mm = 0.5;
  double tracked_target_deg = 0.5;
};

// Defaults for a cell: its correction limits (its approach error budget) go to the planner and
// bound how far from its prior the part is looked for.
ControllerSettings settings_for(const cell::CellSettings& cs);

// What one scan tells: the target's and the part's poses in the scan frame, or why not.
struct Measurement {
  bool ok = false;
  bool target_ok = false;  // the target alone was trusted (T_scan_target is usable)
  std::string reason;
  Pose T_scan_target = Pose::Identity(), T_scan_part = Pose::Identity();
  bool part_axial_unknown = false;  // ambiguous along the part's own axis (harmless)
  // Set when the target's spin about this axis (scan frame) is the prior's, not measured.
  std::optional<Eigen::Vector3d> target_prior_spin_axis;
  bool target_turn_tracked = false;  // its one unobservable turn is its last trusted measurement's
  registration::RegistrationResult target, part;
};

// The decision from a measurement: the correction (world / scan frame, left-multiplied) that puts
// the part at `T_target_part_goal` relative to the measured target.
struct Correction {
  Pose delta = Pose::Identity();
  double lateral_mm = 0;  // residual perpendicular to the insertion axis
  double axial_mm = 0;    // along it (> 0: the part must move further in); 0 when
                          // the scan could not fix the part along its own axis
  double angle_deg = 0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // the insertion axis (scan frame)
};
// with_axial = false: the part is not moved along its own axis (once its end is near or in the
// target, the target hides it and the measured end is short).
Correction compute_correction(const Measurement& m, const Pose& T_target_part_goal,
                              bool with_orientation, bool with_axial = true);

// The correction with its move along the insertion axis limited to max_mm (a trust region: a
// reading that is off moves the part at most that far before the next scan checks it).
Correction limit_axial(Correction c, double max_mm);

// Accept or reject a registration for the task (ok; or ambiguous about the declared harmless DoF).
bool acceptable(const registration::RegistrationResult& r, const std::string& weak_rotation_axis,
                const std::string& weak_translation_axis, const Pose& T_scan_object,
                std::string* why);

// T with its rotation about its own axis `e` (object frame, unit) replaced by the prior's, the
// rest of its orientation and its position kept: for a registration that left that spin
// unobservable (the needle about its shaft).
Pose with_prior_spin(const Pose& T, const Pose& prior, const Eigen::Vector3d& e);

// A target's pose with its one unobservable turn taken from its last trusted measurement
// `tracked` (ControllerSettings::tracked_target_mm), or nothing: not ambiguous about a single
// rotation, or farther from that measurement than a target that has not moved can be.
std::optional<Pose> turn_from_tracked(const registration::RegistrationResult& r,
                                      const Pose& tracked, const ControllerSettings& s);

Measurement measure(
    const PointCloud& scan, const PointCloud& target_ref, const PointCloud& part_ref,
    const Pose& target_prior, const Pose& part_prior, const cell::CellSettings& cs,
    const ControllerSettings& s, uint64_t seed, std::vector<std::string>& log,
    const std::optional<Pose>& tracked_target = std::nullopt,  // an earlier T_scan_target
    const std::optional<Pose>& tracked_part = std::nullopt);   // T_target_part expected
                                                               // from the last measurement

// The trajectory for a correction: from the flange's believed pose (A's base) to the pose that
// applies `delta` (world frame) through the believed base-to-base transform; refused if too large.
planning::Trajectory plan(const cell::Cell& c, const Pose& T_baseA_flange, const Pose& delta,
                          const ControllerSettings& s);
// A correction folded into a step the cell takes anyway (`step`, world frame; the move is
// step * correction): the cell's limit bounds the correction alone, and the combined move is
// checked against that limit widened by the step.
planning::Trajectory plan_folded(const cell::Cell& c, const Pose& T_baseA_flange,
                                 const Pose& correction, const Pose& step,
                                 const ControllerSettings& s);

}  // namespace laserfit::controller

namespace laserfit {
template <>
struct EnumNames<controller::Strategy> {
  static constexpr const char* what = "strategy";
  static constexpr std::pair<controller::Strategy, const char*> table[] = {
      {controller::Strategy::ProprioIC1, "ic1"},
      {controller::Strategy::ProprioIC2, "ic2"},
      {controller::Strategy::Laser, "laser"},
      {controller::Strategy::LaserPose, "laser_pose"}};
};
}  // namespace laserfit
