#pragma once
// The controller run against the simulated cell: teaching, start configurations, scans from the
// sensing arm's true pose, and the insertion outcome judged on the true poses.
#include "laserfit/controller/controller.hpp"

namespace laserfit::controller {

// One test setting (a target pose) of one cell instance, prepared once for every strategy.
struct SimSetup {
  int setting = 0;
  Pose T_world_target;                 // truth
  robot::Joints q_taught;              // the true arm at the insertion, taught near IC1
  Pose p_ins;                          // the recorded insertion flange pose (A's base, nominal fk)
  Pose T_world_target_believed;        // the target as the taught pose implies
  robot::Joints q_ic2_ref;             // IC1 with joint 1 turned
  std::vector<robot::Joints> q_start;  // q^(1..N)
  robot::Joints q_scan;                // sensing arm at the sweep start
  Pose T_world_sensor_start;           // believed (nominal fk)
  robot::Joints q_scan_raised;         // the search pose search_raise_mm farther back (nominal IK)
  Pose T_world_sensor_raised;          // believed (nominal fk)
  PointCloud target_ref, part_ref;     // what the nominal sweep sees of each
};
SimSetup prepare_setting(const cell::Cell& c, int setting, const ControllerSettings& s,
                         uint64_t seed);

struct Outcome {
  Strategy strategy = Strategy::ProprioIC1;
  int setting = 0, start = 0;
  uint64_t seed = 0;
  bool success = false;
  std::string result;  // inserted | missed | refused: <why>
  cell::Insertion insertion;
  int scans = 0, rounds = 0;
  double time_s = 0;
  std::vector<std::string> log;
};
Outcome run_insertion(const cell::Cell& c, const SimSetup& su, Strategy strategy, int start,
                      uint64_t seed, const ControllerSettings& s);
io::Json outcome_json(const Outcome& o);

// A scan of the cell as it truly is, in the frame the sensing arm believes (what the real sensor
// delivers): the sensing arm at q_scan (its repeatability drawn from g), the part where it is.
// sweep_mm > the scene's sweep: a longer sweep about the same centre (a search scan); raised:
// from the sensing arm's raised search pose (q_scan_raised).
PointCloud scan_cell(const cell::Cell& c, const SimSetup& su, const Pose& T_world_part_true,
                     uint64_t seed, std::mt19937_64& g, double sweep_mm = 0, bool raised = false);

}  // namespace laserfit::controller
