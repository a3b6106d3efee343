// The on-line loop against a cell behind its port: the simulated cell gives what `sim` gives, and
// a cell that reports a fault or returns a scan with no data stops the loop at once: the stop is
// sent, no motion command follows, the reason is the outcome.
#include <gtest/gtest.h>

#include "laserfit/controller/sim.hpp"

using namespace laserfit;

namespace {
const std::string kSource = LASERFIT_SOURCE_DIR;

// The simulated cell with one fault injected: the n-th motion (from 1) fails, or every scan from
// the n-th on is empty. Counts what the loop asks after the fault.
class FaultyCell : public controller::CellPort {
 public:
  FaultyCell(controller::SimCell& sim, int fault_move, int empty_scan)
      : sim_(sim), fault_move_(fault_move), empty_scan_(empty_scan) {}
  robot::Joints joints() override { return sim_.joints(); }
  controller::MotionReport move(const controller::MotionCommand& c) override {
    ++moves;
    if (faulted) ++moves_after_fault;
    if (moves == fault_move_) {
      faulted = true;
      controller::MotionReport r;
      r.reason = "joint 4 torque limit";
      return r;
    }
    return sim_.move(c);
  }
  controller::Sweep scan(const controller::SweepRequest& r) override {
    ++scans;
    if (faulted) ++scans_after_fault;
    if (empty_scan_ > 0 && scans >= empty_scan_) return faulted = true, controller::Sweep{};
    return sim_.scan(r);
  }
  void stop() override { ++stops; }
  std::optional<cell::Insertion> judge() override { return sim_.judge(); }
  std::optional<Eigen::Vector2d> true_error(const Pose& goal) override {
    return sim_.true_error(goal);
  }
  int moves = 0, scans = 0, stops = 0, moves_after_fault = 0, scans_after_fault = 0;
  bool faulted = false;

 private:
  controller::SimCell& sim_;
  int fault_move_, empty_scan_;
};

// A needle trial, laser strategy. short_: no intermediate stages and one correction round (the
// loop's every path but the stage moves, in a third of the time).
struct Trial {
  explicit Trial(bool short_ = false) {
    if (!short_) return;
    s.max_rounds = 1;
    c.s.stages.clear();
  }
  cell::CellSettings cs = cell::load_cell(kSource + "/cells/needle.yaml");
  controller::ControllerSettings s = [this] {
    auto s = controller::settings_for(cs);
    s.thresholds = registration::load_thresholds(kSource + "/reports/paper/thresholds_needle.yaml");
    return s;
  }();
  cell::Cell c{cs, 1};
  controller::SimSetup su = controller::prepare_setting(c, 0, s, 1);
  controller::Outcome run(controller::CellPort& cell) {
    return controller::run_insertion(cell, c, su, controller::Strategy::Laser, 0, 9, s);
  }
};
}  // namespace

// Through the port with no fault, the loop is the one `sim` runs: every field of the outcome and
// every line of its log equal (exact: the same seeds drive the same simulated cell).
TEST(CellPort, ThroughThePortTheOutcomeIsSims) {
  Trial t(true);
  controller::SimCell sim(t.c, t.su, 0, 9, t.s.motion);
  FaultyCell cell(sim, 0, 0);
  const auto a = t.run(cell);
  const auto b = controller::run_insertion(t.c, t.su, controller::Strategy::Laser, 0, 9, t.s);
  EXPECT_EQ(a.result, b.result);
  EXPECT_EQ(a.log, b.log);
  EXPECT_EQ(a.scans, b.scans);
  EXPECT_EQ(a.success, b.success);
  EXPECT_EQ(a.insertion.x_mm, b.insertion.x_mm);
  EXPECT_EQ(a.insertion.y_mm, b.insertion.y_mm);
  EXPECT_GE(cell.moves, 3);  // approach, at least one correction, the insertion
  // Completion time: the cell's motions and sweeps (each sweep 6 mm at 10 mm/s: 0.6 s) plus the
  // controller's computation, which excludes the simulation inside the cell's calls.
  EXPECT_GE(a.cell_time_s, 0.6 * a.scans);
  EXPECT_GT(a.compute_s, 0.0);
  EXPECT_LT(a.compute_s, a.time_s);
  EXPECT_DOUBLE_EQ(a.completion_s, a.cell_time_s + a.compute_s);
  EXPECT_EQ(cell.stops, 0);
}

// A fault on the approach and on the first correction: refused with the arm's reason, one stop,
// nothing commanded after the fault (not even a scan).
TEST(CellPort, AFaultStopsTheLoopWithNoFurtherCommand) {
  for (int fault_move : {1, 2}) {
    Trial t;
    controller::SimCell sim(t.c, t.su, 0, 9, t.s.motion);
    FaultyCell cell(sim, fault_move, 0);
    const auto o = t.run(cell);
    EXPECT_EQ(o.result, "refused: the assembling arm reported a fault: joint 4 torque limit");
    EXPECT_FALSE(o.success);
    EXPECT_EQ(cell.stops, 1);
    EXPECT_EQ(cell.moves_after_fault, 0);
    EXPECT_EQ(cell.scans_after_fault, 0);
  }
}

// A scan with no data at all (the scanner delivered nothing) is not re-tried as an untrusted
// registration: the loop stops at once.
TEST(CellPort, AScanWithNoDataStopsTheLoop) {
  Trial t;
  controller::SimCell sim(t.c, t.su, 0, 9, t.s.motion);
  FaultyCell cell(sim, 0, 1);
  const auto o = t.run(cell);
  EXPECT_EQ(o.result, "refused: the cell returned a scan with no data");
  EXPECT_EQ(cell.stops, 1);
  EXPECT_EQ(cell.moves_after_fault, 0);
  EXPECT_EQ(cell.scans_after_fault, 0);
}

// A cell that records the order of the loop's calls: 'm' a motion, 's' a sweep.
class RecordingCell : public controller::CellPort {
 public:
  explicit RecordingCell(controller::SimCell& sim) : sim_(sim) {}
  robot::Joints joints() override { return sim_.joints(); }
  controller::MotionReport move(const controller::MotionCommand& c) override {
    calls += 'm';
    const auto r = sim_.move(c);
    // How deep the part went past the mouth beside the hole (a part through the target's face).
    if (const auto at = sim_.judge(); at && !at->success)
      deepest_outside_mm = std::max(deepest_outside_mm, at->depth_mm);
    return r;
  }
  controller::Sweep scan(const controller::SweepRequest& r) override {
    return calls += 's', sim_.scan(r);
  }
  void stop() override { calls += 'x'; }
  std::optional<cell::Insertion> judge() override { return sim_.judge(); }
  std::optional<Eigen::Vector2d> true_error(const Pose& goal) override {
    return sim_.true_error(goal);
  }
  std::string calls;
  double deepest_outside_mm = -1e9;

 private:
  controller::SimCell& sim_;
};

// Scan only where it pays: a correction goes with the move to the next waypoint, whose scan
// verifies it. The same trial with and without folding: both inserted (the simulated cell judges
// on the true poses: within the eye's 85 um / 425 um clearance), with fewer scans folded, and
// every motion is followed by a scan before the next one.
TEST(CellPort, FoldedCorrectionsAreVerifiedByTheNextWaypointsScan) {
  int scans[2] = {0, 0};
  for (const bool fold : {false, true}) {
    Trial t;
    t.s.fold = fold;
    controller::SimCell sim(t.c, t.su, 0, 9, t.s.motion);
    RecordingCell cell(sim);
    const auto o = t.run(cell);
    EXPECT_TRUE(o.success) << (fold ? "folded: " : "verified: ") << o.result;
    scans[fold] = o.scans;
    if (!fold) continue;
    ASSERT_GE(cell.calls.size(), 2u);
    EXPECT_EQ(cell.calls.back(), 'm');  // the insertion
    EXPECT_EQ(cell.calls.find("mm"), std::string::npos) << cell.calls;
  }
  EXPECT_LT(scans[1], scans[0]);
}

// A guarded move that meets the target's face stops there; the loop then knows the part's depth
// (which no scan of a plug fixes: its front faces away from the scanner), backs off and goes on.
// A USB trial whose plug slipped 8 mm deeper in the gripper after teaching: the approach, planned
// 6 mm above the mouth, touches the plate. Inserted (within the 50 um clearance, judged on the true
// poses); after every motion the plug is at most 3x the arm's 50 um repeatability past the mouth's
// 0.1 mm depth clearance unless it is in the socket (the simulated arm stops at the face, then
// lands within its repeatability); the touch is followed by the back-off and a scan.
TEST(CellPort, AGuardedMoveStopsAtTheFaceAndTheLoopBacksOff) {
  const auto cs = cell::load_cell(kSource + "/cells/usb.yaml");
  auto s = controller::settings_for(cs);
  s.thresholds = registration::load_thresholds(kSource + "/reports/paper/thresholds_usb.yaml");
  cell::Cell c{cs, 1};
  const controller::SimSetup su = controller::prepare_setting(c, 0, s, 1);
  c.T_flange_part_true = c.T_flange_part_true * Eigen::Translation3d(0, 0, 8);  // after teaching
  controller::SimCell sim(c, su, 0, 9, s.motion);
  RecordingCell cell(sim);
  const auto o = controller::run_insertion(cell, c, su, controller::Strategy::Laser, 0, 9, s);
  EXPECT_TRUE(o.success) << o.result;
  EXPECT_NE(std::find(o.log.begin(), o.log.end(),
                      "touched the target's face: backing off to 60 % of the way in"),
            o.log.end());
  EXPECT_LE(cell.deepest_outside_mm, c.s.clearance.depth_mm + 3 * c.s.arm_errors.repeatability_mm);
  EXPECT_EQ(cell.calls.substr(0, 3), "mms") << cell.calls;  // the touch, the back-off, a scan
}

// The last move goes on past the insertion pose by the cell's push_mm, guarded: the USB plug ends
// inside its socket by the push, to within the 0.7 mm a plug seen from behind can be left off
// along its axis, and inserted (judged on the true poses: 50 um, 1 deg, entered). Set down at the
// mouth, as before the push, it would end within 0.7 mm of depth 0, outside this window.
TEST(CellPort, ThePlugIsPushedIntoItsSocket) {
  auto cs = cell::load_cell(kSource + "/cells/usb.yaml");
  ASSERT_EQ(cs.push_mm, 2.0);
  auto s = controller::settings_for(cs);
  s.thresholds = registration::load_thresholds(kSource + "/reports/paper/thresholds_usb.yaml");
  cell::Cell c{cs, 1};
  const controller::SimSetup su = controller::prepare_setting(c, 0, s, 1);
  controller::SimCell sim(c, su, 0, 9, s.motion);
  RecordingCell cell(sim);
  const auto o = controller::run_insertion(cell, c, su, controller::Strategy::LaserPose, 0, 9, s);
  EXPECT_TRUE(o.success) << o.result;
  EXPECT_NEAR(o.insertion.depth_mm, cs.push_mm, 0.7);
  EXPECT_EQ(cell.calls.back(), 'm') << cell.calls;
}

// A cell that reports a contact on a motion the loop did not guard is not believed: the trial
// stops as a cell fault, with the stop sent.
TEST(CellPort, AContactOnAnUnguardedMotionIsAFault) {
  struct Lying : RecordingCell {
    using RecordingCell::RecordingCell;
    controller::MotionReport move(const controller::MotionCommand& c) override {
      auto r = RecordingCell::move(c);
      r.contact = true;
      return r;
    }
  };
  Trial t;
  controller::SimCell sim(t.c, t.su, 0, 9, t.s.motion);
  Lying cell(sim);
  const auto o =
      controller::run_insertion(cell, t.c, t.su, controller::Strategy::ProprioIC1, 0, 9, t.s);
  EXPECT_TRUE(o.cell_fault);
  EXPECT_NE(o.result.find("a contact on an unguarded motion"), std::string::npos) << o.result;
  EXPECT_EQ(cell.calls, "mx");
}

// What a trial learns of the arm's moves is handed to the next in the same cell: the memory holds
// one observation per move the trial logged as learned, and the next trial says it starts from
// them (its scans then fail, to keep the test short). The first, with an empty memory, does not.
TEST(CellPort, WhatATrialLearnsCarriesToTheNext) {
  Trial t(true);
  t.s.max_rounds = 2;  // one correction verified by a scan: a move to learn from
  controller::MotionErrorModel memory(t.s.learning);
  controller::SimCell first(t.c, t.su, 0, 9, t.s.motion);
  const auto a =
      controller::run_insertion(first, t.c, t.su, controller::Strategy::Laser, 0, 9, t.s, &memory);
  const auto learned = std::count_if(a.log.begin(), a.log.end(), [](const std::string& l) {
    return l.find(": learned (") != std::string::npos;
  });
  ASSERT_GT(learned, 0) << a.result;
  EXPECT_EQ(memory.observations(), learned);
  struct Blind : RecordingCell {
    using RecordingCell::RecordingCell;
    controller::Sweep scan(const controller::SweepRequest&) override {
      controller::Sweep s;
      s.fault = "the scanner is off";
      return s;
    }
  };
  controller::SimCell sim(t.c, t.su, 1, 10, t.s.motion);
  Blind second(sim);
  const auto b = controller::run_insertion(second, t.c, t.su, controller::Strategy::Laser, 1, 10,
                                           t.s, &memory);
  const std::string line =
      "moves corrected by what " + std::to_string(learned) + " earlier moves in this cell taught";
  EXPECT_NE(std::find(b.log.begin(), b.log.end(), line), b.log.end());
  EXPECT_EQ(std::find(a.log.begin(), a.log.end(), line), a.log.end());
}
