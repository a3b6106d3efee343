// One insertion attempt with a strategy (the paper's Section IV), against a cell behind its port.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "laserfit/controller/sim.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/sensor/assemble.hpp"

namespace laserfit::controller {
namespace {

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// How far off an unverified move of the arm lands, per length moved (up to; learned moves less).
constexpr double kMoveErrorPerLength = 0.1;

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// One trial: what the loop knows (the cell's reports, its model, its measurements) and the
// outcome it writes. Every motion goes through `move`, which ends the trial on a fault.
class Loop {
 public:
  Loop(CellPort& cell, const cell::Cell& c, const SimSetup& su, Strategy strategy, int start,
       uint64_t seed, const ControllerSettings& s, const MotionErrorModel& learned)
      : cell_(cell), c_(c), su_(su), s_(s), seed_(seed), learned_(learned) {
    o_.strategy = strategy, o_.setting = su.setting, o_.start = start, o_.seed = seed;
  }
  Outcome run();
  const MotionErrorModel& learned() const { return learned_; }

 private:
  Outcome attempt();
  bool move(const Pose& T_baseA_flange_goal, const robot::Joints& q_ref,
            const robot::MotionSettings& ms, bool guarded = false);
  bool shift(const Pose& delta, double min_duration_s);
  bool move_on(const Pose& d);
  bool scan_until_trusted(bool gated, bool outside, Correction& corr);
  bool correct_rounds(bool gated, bool outside, bool next_outside);
  bool stages();
  bool touched(const std::vector<double>& fractions, size_t& w);
  Pose waypoint(double fraction) const;
  bool push_on();
  bool step_aside();
  // The target as last trusted, else where the model puts it (scan / world frame).
  const Pose& target_estimate() const { return tracked_ ? *tracked_ : su_.T_world_target_believed; }
  bool outside(const Pose& waypoint) const;
  double fold_max_mm() const {
    const double clearance = std::min(c_.s.clearance.x_mm, c_.s.clearance.y_mm);
    return s_.fold_max_mm > 0 ? s_.fold_max_mm : 0.25 * clearance / kMoveErrorPerLength;
  }
  PointCloud sweep(const SweepRequest& req);
  void dump(const PointCloud& scan) const;
  Outcome finish();
  Outcome refuse(const std::string& why);

  CellPort& cell_;
  const cell::Cell& c_;
  const SimSetup& su_;
  const ControllerSettings& s_;
  uint64_t seed_;
  Outcome o_;
  std::string why_;                  // why the trial stops: a fault the cell reported, or a refusal
  Pose way_ = Pose::Identity();      // the waypoint being reached (part in the target frame)
  Pose pending_ = Pose::Identity();  // a measured correction to apply with the next move
  double pending_mm_ = 0;            //   how far it moves the part's end (mm)
  double unverified_mm_ = 0;         // as far as the last move's, verified by no scan yet
  bool contact_ = false;             // the last (guarded) move stopped on the target's face
  bool turn_ = true;                 // the next correction turns the part too (pose strategy)
  int touches_ = 0;
  bool stepped_aside_ = false;
  MotionErrorModel learned_;  // the arm's move error, world frame: this cell's earlier moves on
  std::optional<Eigen::Vector3d> measured_at_;  // the part's origin at the last measurement
  Eigen::Vector3d commanded_ = Eigen::Vector3d::Zero();  //   and the moves commanded since
  Eigen::Vector3d turned_ = Eigen::Vector3d::Zero();     //   with their turns (rad; target frame)
  void learn(bool position_measured);
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  double in_cell_s_ = 0;  // wall-clock time spent inside the cell's calls
  double cell_s_ = 0;     // the cell's own time: motions and sweeps as it reports them
  void times();
  Measurement m_;
  std::optional<Pose> tracked_;       // the target's last trusted measurement (scan frame)
  std::optional<Pose> tracked_part_;  // the part relative to the target: last measured, then moved
};

bool Loop::move(const Pose& goal, const robot::Joints& q_ref, const robot::MotionSettings& ms,
                bool guarded) {
  // The path from where the arm reports its flange (its joints through the nominal model, as the
  // arm's own controller computes it), checked before it is sent.
  MotionCommand cmd;
  cmd.path = robot::plan_cartesian(c_.nominal.fk(cell_.joints()), goal, ms), cmd.q_ref = q_ref;
  cmd.guarded = guarded;
  if (const std::string bad = check_request(cmd, c_.nominal); !bad.empty())
    return why_ = "not sent: " + bad, false;
  const auto t = std::chrono::steady_clock::now();
  const MotionReport r = cell_.move(cmd);
  in_cell_s_ += since(t);
  std::string bad = check_report(r, c_.nominal.limits);
  if (bad.empty() && r.contact && !guarded) bad = "a contact on an unguarded motion";
  if (!bad.empty())
    return o_.cell_fault = true, why_ = "the assembling arm's report: " + bad, false;
  cell_s_ += r.duration_s;
  contact_ = r.contact;
  if (!r.ok) o_.cell_fault = true, why_ = "the assembling arm reported a fault: " + r.reason;
  return r.ok;
}

// Moves the part by `delta` (scan / world frame) holding the elbow: a null-space drift toward IC2
// would move the true flange by the model error while the nominal one stays put.
bool Loop::shift(const Pose& delta, double min_duration_s) {
  robot::MotionSettings ms = s_.motion;
  ms.min_duration_s = min_duration_s;
  const robot::Joints hold = cell_.joints();
  const Pose& B = c_.T_world_baseA_believed;
  Pose command = delta;  // the part's origin moved by what lands the wanted move (learned)
  if (tracked_part_) {
    const Eigen::Matrix3d R = m_.T_scan_target.linear();
    const Eigen::Vector3d o = m_.T_scan_target * tracked_part_->translation();
    const Eigen::Vector3d wanted = R.transpose() * (delta * o - o);
    const Eigen::AngleAxisd turn(delta.linear());
    const Eigen::Vector3d w = turn.angle() * turn.axis();
    const Eigen::Vector3d c = R.transpose() * learned_.command_for(R * wanted, w);
    command.pretranslate(R * (c - wanted));
    commanded_ += c, turned_ += R.transpose() * w;
  }
  if (!move(B.inverse() * command * B * c_.nominal.fk(hold), hold, ms, true)) return false;
  if (tracked_part_)
    tracked_part_ = m_.T_scan_target.inverse() * delta * m_.T_scan_target * *tracked_part_;
  return true;
}

// A move on toward the insertion (`d`, world frame), with the correction folded into it if any:
// the correction first (it puts the part on the current waypoint), then the step from there.
bool Loop::move_on(const Pose& d) {
  const Pose D = d * pending_;
  unverified_mm_ = pending_mm_;
  if (pending_.isApprox(Pose::Identity())) return shift(D, s_.motion.min_duration_s);
  const Pose correction = pending_;
  pending_ = Pose::Identity(), pending_mm_ = 0;
  const auto tr = plan_folded(c_, c_.nominal.fk(cell_.joints()), correction, d, s_);
  if (!tr.ok) return why_ = tr.reason, false;
  return shift(D, std::max(tr.duration_s, s_.motion.min_duration_s));
}

void Loop::times() {
  o_.time_s = since(t0_);
  o_.cell_time_s = cell_s_;
  o_.compute_s = std::max(0.0, o_.time_s - in_cell_s_);
  o_.completion_s = o_.cell_time_s + o_.compute_s;
}

Outcome Loop::finish() {
  if (const auto j = cell_.judge()) {
    o_.insertion = *j, o_.success = j->success;
    o_.result = o_.success ? "inserted" : "missed";
  } else {
    // A cell that cannot judge the insertion is not counted a success: the motion completed,
    // whether the part went in is the lab's to record.
    o_.result = "insertion motion done (not judged by the cell)";
  }
  o_.log.push_back("insertion: lateral (" + fmt(o_.insertion.x_mm * 1e3) + ", " +
                   fmt(o_.insertion.y_mm * 1e3) + ") um, depth " +
                   fmt(o_.insertion.depth_mm * 1e3) + " um, axis " + fmt(o_.insertion.angle_deg) +
                   " deg -> " + o_.result);
  times();
  return o_;
}

Outcome Loop::refuse(const std::string& why) {  // never insert blind
  cell_.stop();
  o_.result = "refused: " + why;
  o_.log.push_back(o_.result);
  if (const auto j = cell_.judge()) o_.insertion = *j;
  times();
  return o_;
}

// A cell that fails on a call (a lost peer, a malformed reply) throws: the trial stops there as a
// refusal, with the stop sent, like a fault the cell reports. Any other error is refused too.
Outcome Loop::run() {
  try {
    return attempt();
  } catch (const CellFailure& e) {
    o_.cell_fault = true;
    return refuse(e.what());
  } catch (const Error& e) {
    return refuse(e.what());
  }
}

Outcome Loop::attempt() {
  const Strategy st = o_.strategy;
  const robot::Joints& q_ref = st == Strategy::ProprioIC1 ? su_.q_taught : su_.q_ic2_ref;
  if (st == Strategy::ProprioIC1 || st == Strategy::ProprioIC2) {
    o_.log.push_back(
        std::string("proprioception only, ") + (st == Strategy::ProprioIC1 ? "IC1" : "IC2") +
        ": reach the recorded insertion pose from start " + std::to_string(o_.start + 1));
    return move(su_.p_ins, q_ref, s_.motion) && push_on() ? finish() : refuse(why_);
  }
  // Laser feedback: approach (IC2), then scan, register, correct, verify; finally insert.
  Pose approach = c_.s.T_target_part_insert;
  approach.translation() = c_.s.approach_mm;
  if (!move(c_.flange_for_part(su_.T_world_target_believed * approach), q_ref, s_.motion, true))
    return refuse(why_);
  o_.log.push_back("approach with IC2 from start " + std::to_string(o_.start + 1));
  if (learned_.observations() > 0)
    o_.log.push_back("moves corrected by what " + std::to_string(learned_.observations()) +
                     " earlier moves in this cell taught");
  way_ = approach;
  return stages() ? finish() : refuse(why_);
}

// The part's waypoint `fraction` of the way from the approach to the insertion (target frame).
Pose Loop::waypoint(double fraction) const {
  const auto& cs = c_.s;
  Pose p = cs.T_target_part_insert;
  p.translation() = cs.T_target_part_insert.translation() +
                    (cs.approach_mm - cs.T_target_part_insert.translation()) * (1 - fraction);
  return p;
}

// From the insertion pose on along the insertion axis (the target as last measured, else as the
// model puts it) by the cell's push_mm, guarded: a plug is pushed into its socket.
bool Loop::push_on() {
  if (c_.s.push_mm <= 0) return true;
  Pose d = Pose::Identity();
  d.translation() =
      target_estimate().linear() * c_.s.T_target_part_insert.linear().col(2) * c_.s.push_mm;
  if (!shift(d, s_.motion.min_duration_s)) return false;
  o_.log.push_back(contact_ ? "pushed on: stopped on the target's face"
                            : "pushed on " + fmt(c_.s.push_mm) + " mm along the insertion axis");
  return true;
}

// The part steps aside by the cell's clear_view_mm (target frame), guarded, for the next scan to
// see the target without it (CellSettings::clear_view_mm says when that is needed).
bool Loop::step_aside() {
  stepped_aside_ = true;
  Pose d = Pose::Identity();
  d.translation() = target_estimate().linear() * c_.s.clear_view_mm;
  if (!shift(d, s_.motion.min_duration_s)) return false;
  if (contact_) return why_ = "the part met the target stepping aside to clear the view", false;
  o_.log.push_back("target not trusted with the part in front of it: the part steps " +
                   fmt(c_.s.clear_view_mm.norm()) + " mm aside for the next scan");
  return true;
}

// Whether the part's end is still outside the target there (short of its mouth).
bool Loop::outside(const Pose& w) const {
  const Pose& Q = c_.s.T_target_part_insert;
  return (w.translation() - Q.translation()).dot(Q.linear().col(2)) < -c_.s.clearance.depth_mm;
}

// Waypoints from the approach toward the insertion, each reached and verified by scans: an
// unverified move of d mm on an arm whose model is off by a few degrees lands d * sin(error)
// off, so the last unverified step is kept short. The last move inserts, along the measured
// target, then pushes on (push_on). A guarded move that ends on the target's face goes back to
// the first stage (touched).
bool Loop::stages() {
  std::vector<double> fractions = {0.0};
  fractions.insert(fractions.end(), c_.s.stages.begin(), c_.s.stages.end());
  for (size_t w = 0;;) {  // the part is at way_, waypoint w (the approach first)
    if (contact_ && !touched(fractions, w)) return false;
    // The move after the last stage is the insertion: into the target.
    const bool next_outside = w + 1 < fractions.size() && outside(waypoint(fractions[w + 1]));
    // After the approach has been corrected and verified, the axial trust region applies; a
    // larger correction carried by the move here is verified only by this waypoint's scan, and
    // a part the last scan could not place along its axis (`ambiguous` there) was not verified
    // along it at all: its next reading along the axis is news, not an implausible one.
    const bool gated = w > 0 && unverified_mm_ <= s_.axial_gate_mm && !m_.part_axial_unknown;
    if (!correct_rounds(gated, outside(way_), next_outside)) return false;
    if (contact_) continue;
    const Pose next = ++w < fractions.size() ? waypoint(fractions[w]) : waypoint(1.0);
    Pose d = Pose::Identity();
    d.translation() = m_.T_scan_target.linear() * (next.translation() - way_.translation());
    if (!move_on(d)) return false;
    if (contact_) continue;
    if (w == fractions.size()) {
      if (!push_on()) return false;
      if (contact_) continue;  // not in the hole after all: back off and look again
      return true;
    }
    o_.log.push_back("stage " + std::to_string(w) + ": " + fmt(100 * fractions[w]) +
                     " % of the way in");
    way_ = next;
  }
}

// A guarded move stopped where the part met the target's face: its end is at the mouth plane,
// beside the hole. That fixes what no scan could, its position along the axis (a plug whose
// front faces away from the scanner, an approach mm deeper than the arm's model says): the loop's
// waypoint and the part's prior move there, and the part backs off to the first stage.
bool Loop::touched(const std::vector<double>& fractions, size_t& w) {
  contact_ = false;
  if (++touches_ > s_.max_touches)
    return why_ = "the part met the target's face " + std::to_string(touches_) + " times", false;
  const Pose& Q = c_.s.T_target_part_insert;
  const Eigen::Vector3d n = Q.linear().col(2);
  auto on_face = [&](Pose p) {
    p.translation() += n * n.dot(Q.translation() - p.translation());
    return p;
  };
  tracked_part_ = on_face(tracked_part_ ? *tracked_part_
                                        : su_.T_world_target_believed.inverse() *
                                              c_.part_believed(cell_.joints()));
  way_ = on_face(way_);
  // The interrupted move teaches nothing.
  measured_at_.reset(), commanded_.setZero(), turned_.setZero();
  pending_ = Pose::Identity(), pending_mm_ = 0;
  turn_ = true;  // the interrupted move had not finished turning the part
  w = std::min<size_t>(1, fractions.size() - 1);
  const Pose back = waypoint(fractions[w]);
  o_.log.push_back("touched the target's face: backing off to " + fmt(100 * fractions[w]) +
                   " % of the way in");
  // Before any measurement (a contact on the approach) the target is where the model puts it.
  if (!m_.target_ok) m_.T_scan_target = target_estimate();
  Pose d = Pose::Identity();
  d.translation() = m_.T_scan_target.linear() * (back.translation() - way_.translation());
  if (!shift(d, s_.motion.min_duration_s)) return false;
  way_ = back;
  return true;
}

// Measure, correct, verify by the next measurement, until settled or out of rounds; or, where it
// is safe, leave the correction to go with the next move, whose scan verifies it.
bool Loop::correct_rounds(bool gated, bool outside, bool next_outside) {
  const bool orient = o_.strategy == Strategy::LaserPose;
  for (int round = 0; round <= s_.max_rounds; ++round, ++o_.rounds) {
    Correction corr;
    if (!scan_until_trusted(gated, outside, corr)) return false;
    if (const auto e = cell_.true_error(way_))  // a simulation's truth, for the log only
      o_.log.push_back("  truth (simulation only): lateral error " + fmt(e->x() * 1e3) +
                       " um, along the axis " + fmt(e->y() * 1e3) + " um");
    o_.log.push_back("round " + std::to_string(o_.rounds + 1) + ": measured lateral error " +
                     fmt(corr.lateral_mm * 1e3) + " um, along the axis " +
                     fmt(corr.axial_mm * 1e3) + " um, axis " + fmt(corr.angle_deg) + " deg");
    const bool settled = corr.lateral_mm < s_.verify_mm &&
                         std::abs(corr.axial_mm) < s_.verify_axial_mm &&
                         (!orient || corr.angle_deg < c_.s.clearance.angle_deg / 2);
    // Along the axis at most the trust region once gated.
    const Correction step = gated ? limit_axial(corr, s_.axial_gate_mm) : corr;
    const double tip_mm = std::hypot(step.lateral_mm, step.axial_mm);  // the part's end moves
    if (s_.fold && (next_outside || tip_mm <= fold_max_mm())) {
      pending_ = step.delta, pending_mm_ = tip_mm, ++o_.rounds;
      const double turn_deg = Eigen::AngleAxisd(step.delta.linear()).angle() * 180 / M_PI;
      o_.log.push_back("correction of " + fmt(tip_mm * 1e3) + " um, " + fmt(turn_deg) +
                       " deg goes with the next move");
      break;
    }
    if (settled && (round > 0 || gated)) break;
    // Correct, in the last round too: its reading is still the best estimate (applied
    // unverified, like a stage move).
    const planning::Trajectory tr = plan(c_, c_.nominal.fk(cell_.joints()), step.delta, s_);
    if (!tr.ok) return why_ = tr.reason, false;
    if (!shift(step.delta, tr.duration_s)) return false;
    if (contact_) return true;  // stopped on the target's face: stages() backs off
    o_.log.push_back("corrected: " + fmt(tr.translation_mm * 1e3) + " um, " + fmt(tr.rotation_deg) +
                     " deg in " + fmt(tr.duration_s) + " s" +
                     (round == s_.max_rounds ? " (last round, unverified)" : ""));
    if (round == s_.max_rounds) break;
  }
  return true;
}

// Scans until both registrations are trusted (at most max_scans), widening the search when the
// target is seen but not the part; `corr` is the correction the last trusted measurement asks.
bool Loop::scan_until_trusted(bool gated, bool outside, Correction& corr) {
  const auto& cs = c_.s;
  const bool orient = o_.strategy == Strategy::LaserPose;
  m_ = Measurement{};
  // The scene's sweep, from the taught scan pose; the trial's first scan may sweep longer.
  double sweep_mm = o_.scans == 0 ? cs.approach_sweep_mm : 0;
  bool raised = false;
  for (int k = 0; k < s_.max_scans && !m_.ok; ++k) {
    const uint64_t seed = scan_seed(seed_, o_.scans);
    const PointCloud scan = sweep(sweep_request(c_, su_, sweep_mm, raised));
    ++o_.scans;
    if (scan.points.empty()) return false;
    if (!s_.dump_dir.empty()) dump(scan);
    m_ = measure(scan, su_.target_ref, su_.part_ref, su_.T_world_target_believed,
                 c_.part_believed(cell_.joints()), cs, s_, seed, o_.log, tracked_, tracked_part_);
    if (m_.target_ok) tracked_ = m_.T_scan_target;
    if (!m_.target_ok && !tracked_ && !stepped_aside_ && k + 1 < s_.max_scans &&
        c_.s.clear_view_mm.norm() > 0) {
      if (!step_aside()) return false;
      continue;
    }
    // The target was seen but not the part: the approach may have left it outside the sweep,
    // and then (not in the long sweep either) nearer to the scanner than its measuring range.
    const std::string not_found =
        "no trusted " + cs.scene.objects[cs.part].name + " near the target: next scan ";
    if (m_.target_ok && !m_.ok && sweep_mm < cs.search_sweep_mm) {
      sweep_mm = cs.search_sweep_mm;
      o_.log.push_back(not_found + "sweeps " + fmt(sweep_mm) + " mm");
    } else if (m_.target_ok && !m_.ok && !raised && cs.search_raise_mm > 0) {
      raised = true;
      o_.log.push_back(not_found + "from " + fmt(cs.search_raise_mm) + " mm farther back");
    }
    if (!m_.ok) continue;
    // The pose strategy corrects the orientation in the first round, the position after.
    // Along its axis the part is corrected while its end is still outside the target (above
    // the mouth): an IC2 approach leaves millimetres there, and each unverified move of d mm
    // lands ~0.1 d off. Inside, the target hides the end and the measured end is short.
    corr = compute_correction(m_, way_, orient && turn_, outside);
    if (gated && std::abs(corr.axial_mm) > s_.axial_gate_mm && k + 1 < s_.max_scans) {
      m_.ok = false;  // a thread end cut short or lengthened by the needle under it: look again
      o_.log.push_back("implausible: " + fmt(corr.axial_mm * 1e3) +
                       " um along the axis after a verified move; re-scan");
    } else {
      tracked_part_ = m_.T_scan_target.inverse() * m_.T_scan_part;
      learn(!m_.part_axial_unknown);
      turn_ = false;
    }
  }
  if (!m_.ok) why_ = m_.reason + " after " + std::to_string(s_.max_scans) + " scans";
  return m_.ok;
}

// The moves since the last measurement against what this one measured: the arm's error on them
// (target frame), across the insertion axis only: what the clearance asks and what a scan
// measures well. Along the axis a thread's end measures up to ~0.3 mm short or long, and learning
// from that made the next moves worse. Not from a part whose slide along its own axis the scan
// could not fix (its origin is arbitrary along it, and the axis is tilted).
void Loop::learn(bool position_measured) {
  if (!s_.learning.enabled) return;
  const Eigen::Vector3d at = tracked_part_->translation();
  if (measured_at_ && position_measured && commanded_.norm() > 0) {
    const Eigen::Vector3d axis = c_.s.T_target_part_insert.linear().col(2);
    Eigen::Vector3d error = at - *measured_at_ - commanded_;
    error -= axis * axis.dot(error);
    const Eigen::Matrix3d& R = m_.T_scan_target.linear();  // a frame fixed to the arm's base
    const bool used = learned_.observe(R * commanded_, R * turned_, R * error);
    o_.log.push_back("the arm's move of " + fmt(commanded_.norm() * 1e3) + " um landed " +
                     fmt(error.norm() * 1e3) + " um off it across the axis: " +
                     (used ? "learned (" + std::to_string(learned_.observations()) + " moves)"
                           : "not learned from (a mismeasured move)"));
  }
  measured_at_ = position_measured ? std::optional<Eigen::Vector3d>(at) : std::nullopt;
  commanded_.setZero(), turned_.setZero();
}

// One sweep, assembled into the cloud registration takes (A's believed world frame) exactly as
// `laserfit assemble` does; an empty cloud when the trial stops (a fault, no data, a bad report).
PointCloud Loop::sweep(const SweepRequest& req) {
  const auto t = std::chrono::steady_clock::now();
  const Sweep sw = cell_.scan(req);
  in_cell_s_ += since(t);
  const int width = c_.s.scene.settings.sensor.points_per_profile;
  if (!sw.fault.empty())
    return o_.cell_fault = true, why_ = "the sensing arm reported a fault: " + sw.fault,
           PointCloud{};
  if (const std::string bad = check_report(sw, width); !bad.empty())
    return o_.cell_fault = true, why_ = "the cell's scan: " + bad, PointCloud{};
  cell_s_ += sw.duration_s;
  if (sw.profiles.count == 0)
    return o_.cell_fault = true, why_ = "the cell returned a scan with no data", PointCloud{};
  return sensor::assemble_scan(sw.profiles, sw.T_world_flange, c_.s.T_flange_sensor);
}

void Loop::dump(const PointCloud& scan) const {
  const std::string tag = "_s" + std::to_string(su_.setting), dir = s_.dump_dir + "/";
  io::write_cloud(dir + name_of(o_.strategy) + tag + "_start" + std::to_string(o_.start + 1) +
                      "_scan" + std::to_string(o_.scans) + ".pcd",
                  scan);
  io::write_cloud(dir + "target_ref" + tag + ".pcd", su_.target_ref);
  io::write_cloud(dir + "part_ref" + tag + ".pcd", su_.part_ref);
}

}  // namespace

Outcome run_insertion(CellPort& cell, const cell::Cell& c, const SimSetup& su, Strategy strategy,
                      int start, uint64_t seed, const ControllerSettings& s,
                      MotionErrorModel* learned) {
  Loop loop(cell, c, su, strategy, start, seed, s,
            learned ? *learned : MotionErrorModel(s.learning));
  Outcome o = loop.run();
  if (learned) *learned = loop.learned();
  return o;
}

Outcome run_insertion(const cell::Cell& c, const SimSetup& su, Strategy strategy, int start,
                      uint64_t seed, const ControllerSettings& s, MotionErrorModel* learned) {
  SimCell cell(c, su, start, seed, s.motion);
  return run_insertion(cell, c, su, strategy, start, seed, s, learned);
}

}  // namespace laserfit::controller
