#pragma once
// The simulated dual-arm cell (issue 6): two Pandas in a shared world frame (the sensing arm's
// base), the scanner on the sensing arm, the part (thread, plug) in the assembling arm's gripper,
// the target (needle, socket) in the workspace. Everything the controller *believes* (nominal
// kinematics, calibrated base-to-base, flange-to-sensor and grasp transforms) differs from the
// truth by configured, seeded errors. Lengths mm, angles deg in files.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "laserfit/core/rng.hpp"
#include "laserfit/robot/arm.hpp"
#include "laserfit/robot/error_model.hpp"
#include "laserfit/scan/scanner.hpp"

namespace laserfit::cell {

// A rigid error [x y z (mm), rx ry rz (deg)], applied on the right: true = believed * error.
using RigidError = std::array<double, 6>;
Pose error_pose(const RigidError& e);

struct Clearance {
  double x_mm = 0.075, y_mm = 0.075;  // half-widths at the mouth, target frame
  double angle_deg = 2.0;             // between the part's and the required insertion axis
  double depth_mm = 0.0;              // how far short of the insertion point (along its axis) the
                                      // part's tip may stop and still count: it must have entered
                                      // (0: at least at the insertion point)
};

struct CellSettings {
  std::string file, task;
  scan::ScanScene scene;           // meshes, sensor, sweep (relative to the scene's target)
  int target = -1, part = -1;      // scene objects
  std::vector<Pose> target_poses;  // T_world_target of each test setting (truth)
  Pose T_target_part_insert = Pose::Identity();  // part pose at insertion, target frame
  Eigen::Vector3d approach_mm = {0, 0, 0};       // part's approach position, target frame
  std::vector<double> stages;                    // verified waypoints toward the insertion, as
                                                 // fractions of the approach distance (0..1)
  // How far past the insertion pose the last move pushes along the insertion axis (mm), guarded:
  // a plug is pushed into its socket, not set down at the mouth, so an axial error the scans
  // left (a plug seen from behind) leaves it in, not short; a misaligned part meets the face.
  double push_mm = 0;
  // Where the part steps to (target frame, mm) when the target cannot be trusted with the part in
  // front of it and has not been yet: an IC2 approach can leave the USB plug mm across the
  // socket's mouth, and the plug and its shadow hide what pins the socket. The next scan sees the
  // target alone; the correction from there brings the part back, measured. Zero: no step.
  Eigen::Vector3d clear_view_mm = {0, 0, 0};
  // The largest correction the controller may make in one move (mm, deg): the cell's approach
  // error budget (the arms' model error after an IC2 approach), and how far from its prior the
  // part is looked for. Larger measured corrections are refused.
  double max_correction_mm = 5, max_correction_deg = 5;
  Clearance clearance;
  // The assembling arm: base in the world, the part in its gripper.
  Pose T_world_baseA = Pose::Identity();
  RigidError baseA_error{};  // believed base-to-base calibration -> true
  Pose T_flange_part = Pose::Identity();
  RigidError grasp_error{};
  // The sensing arm (base = world): the scanner on its flange.
  Pose T_flange_sensor = Pose::Identity();
  RigidError sensor_error{};
  robot::ErrorModelSettings arm_errors;
  robot::Joints q_teach_hint = robot::Joints::Zero();  // assembling arm near IC1 when teaching
  robot::Joints q_sense_hint = robot::Joints::Zero();  // sensing arm near its scan pose
  double search_sweep_mm = 0;    // when the part is not found, re-scan with a sweep this long
                                 // (same centre); 0: the scene's sweep only
  double approach_sweep_mm = 0;  // the trial's first scan, after the proprioceptive approach
                                 // (where the part is least known), sweeps this long (same
                                 // centre); 0: the scene's sweep
  double search_raise_mm = 0;    // when not found in the search sweep either, the next scan
                                 // is taken from this much farther back along the view axis
                                 // (the part may be nearer than the measuring range); 0: no
  double ic2_joint1_deg = 90;    // IC2 = IC1 with this added to joint 1
  int start_configs = 10;        // q^(1..N), each farther from the insertion pose
  double start_step_mm = 25;     //   the i-th starts i * step from it
  // DoFs a registration may leave unobservable without harm (an `ambiguous` about them is
  // accepted): the needle's spin about its shaft, the thread's spin and slide along its own
  // axis. "" or x|y|z (object frame).
  std::string target_weak_rotation, target_weak_translation, part_weak_rotation,
      part_weak_translation;
};

CellSettings load_cell(const std::string& path);  // strict YAML; errors name the file and key

// One instance of the cell: the true arms drawn from `robot_seed`.
struct Cell {
  CellSettings s;
  robot::ArmModel nominal, trueA, trueS;
  Pose T_world_baseA_believed, T_world_baseA_true;
  Pose T_flange_part_true, T_flange_sensor_true;

  Cell(const CellSettings& settings, uint64_t robot_seed);
  // Where the part really is when the assembling arm's joints are q (plus repeatability noise,
  // correlated with the arm's previous poses through `rep`).
  Pose part_true(const robot::Joints& qA, robot::Repeatability& rep, Mt19937_64& g) const;
  // Where the controller believes the part is (nominal kinematics, believed calibration).
  Pose part_believed(const robot::Joints& qA) const;
  Pose part_believed_from_flange(const Pose& T_baseA_flange) const;
  // The flange pose (A's base, believed) that puts the part at T_world_part by the controller's
  // belief.
  Pose flange_for_part(const Pose& T_world_part) const;
};

// Insertion outcome of a true part pose against the true target: lateral offset where the part's
// axis crosses the mouth plane, and the axis angle.
struct Insertion {
  bool success = false;
  double x_mm = 0, y_mm = 0,
         angle_deg = 0;  // where the part's axis crosses the mouth (insertion frame)
  double depth_mm = 0;   // its tip past the insertion point along the axis (< 0: short)
};
Insertion check_insertion(const CellSettings& s, const Pose& T_world_target,
                          const Pose& T_world_part);

// Where a rigid part moving from `from` to `to` (true poses, world; a straight line, the rotation
// slerped, sampled every `step_mm`) first runs into the target: its front inside the target's body
// (the target mesh's extent in the insertion frame: past its near face by more than the depth
// clearance, not beyond its far face) while its axis crosses that face outside the hole's
// clearance, deeper than it started (a part resting on the face may leave it). The part stops at
// the last free sample, `travelled_mm` along the way (a real arm's collision reflex). None: free.
// A part that has entered the hole (its front past the depth clearance, its axis within the
// clearance) is guided by the hole's walls from there (`entered`): no contact after that.
struct Contact {
  Pose T_world_part;
  double travelled_mm = 0;
  Insertion at;  // the blocked sample, as the insertion check reads it
};
std::optional<Contact> first_contact(const CellSettings& s, const Pose& T_world_target,
                                     const Pose& from, const Pose& to, double step_mm = 0.1,
                                     bool* entered = nullptr);

// A part in the hole, held by the walls: moved across the insertion axis until that axis crosses
// the mouth within the clearance (a compliant arm yields a fraction of a millimetre sideways; a
// stiff one would jam, which this does not model). Its orientation and depth are kept.
Pose guided(const CellSettings& s, const Pose& T_world_target, const Pose& T_world_part);

}  // namespace laserfit::cell
