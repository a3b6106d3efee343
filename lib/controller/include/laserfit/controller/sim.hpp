#pragma once
// The controller run against the simulated cell: teaching, start configurations, scans from the
// sensing arm's true pose, and the insertion outcome judged on the true poses.
#include <map>
#include <memory>

#include "laserfit/controller/cell_port.hpp"
#include "laserfit/controller/controller.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/robot/error_model.hpp"

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

// Trial i of a seeded campaign: setting i mod S, start (i / S) mod N, robot instance i / (S N)
// (a new seeded arm pair), and its own seed. Everything about trial i follows from (seed, i), so
// a range of trials gives the same outcomes as the same trials inside a longer run.
struct TrialPlan {
  int trial = 0, robot = 0, setting = 0, start = 0;
  uint64_t seed = 0;
};
TrialPlan plan_trial(const cell::CellSettings& cs, uint64_t campaign_seed, int trial);

// The cell instances and settings a campaign's trials need, each prepared once (prepare() them
// before the trials run in parallel; the accessors are then read-only).
class Campaign {
 public:
  Campaign(const cell::CellSettings& cs, const ControllerSettings& s, uint64_t seed)
      : cs_(cs), s_(s), seed_(seed) {}
  void prepare(const TrialPlan& t);
  const cell::Cell& cell(int robot) const { return *cells_.at(robot); }
  const SimSetup& setup(int robot, int setting) const { return setups_.at({robot, setting}); }
  uint64_t seed() const { return seed_; }

 private:
  cell::CellSettings cs_;
  ControllerSettings s_;
  uint64_t seed_;
  std::map<int, std::unique_ptr<cell::Cell>> cells_;
  std::map<std::pair<int, int>, SimSetup> setups_;
};

// The simulated cell behind the port, for one trial: the true arms (kinematic errors,
// repeatability), the scanner simulator from the sensing arm's true pose, the insertion judged
// on the true poses. Its noise follows from `seed`: each scan's from the seed and the number of
// scans before it (the loop seeds its registrations the same way, see scan_seed).
class SimCell : public CellPort {
 public:
  // `arm`: the assembling arm's Cartesian controller (its null-space gain and damping).
  SimCell(const cell::Cell& c, const SimSetup& su, int start, uint64_t seed,
          const robot::MotionSettings& arm = {});
  robot::Joints joints() override { return q_; }
  MotionReport move(const MotionCommand& command) override;
  Sweep scan(const SweepRequest& request) override;
  void stop() override {}
  std::optional<cell::Insertion> judge() override;
  std::optional<Eigen::Vector2d> true_error(const Pose& T_target_part_goal) override;

 private:
  const cell::Cell& c_;
  const SimSetup& su_;
  uint64_t seed_;
  robot::MotionSettings arm_;
  Mt19937_64 g_;
  robot::Repeatability rep_;
  robot::Joints q_;
  std::optional<Pose> part_;  // the part's true pose (world) once the arm has moved
  int scans_ = 0;
};

// The seed of the n-th scan of a trial (n from 0): its noise in the simulated cell and its
// registrations in the loop.
uint64_t scan_seed(uint64_t trial_seed, int n);

// The on-line loop against any cell: `c` is the cell's model (nominal kinematics and believed
// calibration; its true parts are not read), `su` its taught poses and references. `learned`,
// when given, is what the earlier insertions in this cell taught about the assembling arm's moves
// (motion_error.hpp, world frame): the trial starts from it and leaves its own moves in
// it, as an operator's cell learns. Without it every trial starts knowing nothing.
struct Outcome;
Outcome run_insertion(CellPort& cell, const cell::Cell& c, const SimSetup& su, Strategy strategy,
                      int start, uint64_t seed, const ControllerSettings& s,
                      MotionErrorModel* learned = nullptr);

struct Outcome {
  Strategy strategy = Strategy::ProprioIC1;
  int setting = 0, start = 0;
  uint64_t seed = 0;
  bool success = false;
  std::string result;       // inserted | missed | refused: <why>
  bool cell_fault = false;  // the cell stopped the trial: a fault, no data, a lost or lying peer
  cell::Insertion insertion;
  int scans = 0, rounds = 0;
  double time_s = 0;  // wall-clock time of the whole trial, the simulation included
  // Completion time, as the NIST task board protocol scores it: the cell's time (motions with
  // their settling, sweeps) plus the controller's own computation (time_s less the time spent
  // inside the cell's calls), and their sum.
  double cell_time_s = 0, compute_s = 0, completion_s = 0;
  std::vector<std::string> log;
};
Outcome run_insertion(const cell::Cell& c, const SimSetup& su, Strategy strategy, int start,
                      uint64_t seed, const ControllerSettings& s,
                      MotionErrorModel* learned = nullptr);
io::Json outcome_json(const Outcome& o);

// The sweep the loop asks for: the scene's, from the taught scan pose; sweep_mm > the scene's
// sweep: a longer one about the same centre (a search scan); raised: from the sensing arm's
// raised search pose (q_scan_raised).
SweepRequest sweep_request(const cell::Cell& c, const SimSetup& su, double sweep_mm = 0,
                           bool raised = false);

// A sweep of the cell as it truly is, in the frame the sensing arm believes (what the real sensor
// delivers): the sensing arm at r.q_start (its repeatability drawn from g), the part where it is.
scan::ScanResult sweep_cell(const cell::Cell& c, const SimSetup& su, const Pose& T_world_part_true,
                            uint64_t seed, Mt19937_64& g, const SweepRequest& r);
// Its cloud, for the sweep_request(c, su, sweep_mm, raised).
PointCloud scan_cell(const cell::Cell& c, const SimSetup& su, const Pose& T_world_part_true,
                     uint64_t seed, Mt19937_64& g, double sweep_mm = 0, bool raised = false);

}  // namespace laserfit::controller
