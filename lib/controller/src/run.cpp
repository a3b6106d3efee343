// One insertion attempt with a strategy, judged on the true poses.
#include <chrono>
#include <cmath>
#include <sstream>

#include "laserfit/controller/sim.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/io/cloud_io.hpp"

namespace laserfit::controller {
namespace {

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// Moves the assembling arm (nominal model, null-space pull to q_ref) and returns where the part
// truly ends up; the arm's joints are updated.
Pose move(const cell::Cell& c, robot::Joints& q, const Pose& goal, const robot::Joints& q_ref,
          const robot::MotionSettings& ms, robot::Repeatability& rep, std::mt19937_64& g) {
  q = robot::move_cartesian(c.nominal, q, goal, q_ref, ms).q;
  return c.part_true(q, rep, g);
}

}  // namespace

Outcome run_insertion(const cell::Cell& c, const SimSetup& su, Strategy strategy, int start,
                      uint64_t seed, const ControllerSettings& s) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto& cs = c.s;
  Outcome o;
  o.strategy = strategy, o.setting = su.setting, o.start = start, o.seed = seed;
  std::mt19937_64 g = block_rng(seed, 0xC0, 0);
  robot::Joints q = su.q_start.at(start);
  robot::Repeatability rep(cs.arm_errors);
  const robot::Joints& q_ref = strategy == Strategy::ProprioIC1 ? su.q_taught : su.q_ic2_ref;
  auto finish = [&](const Pose& part) {
    o.insertion = cell::check_insertion(cs, su.T_world_target, part);
    o.success = o.insertion.success;
    if (o.result.empty()) o.result = o.success ? "inserted" : "missed";
    o.log.push_back("insertion: lateral (" + fmt(o.insertion.x_mm * 1e3) + ", " +
                    fmt(o.insertion.y_mm * 1e3) + ") um, depth " + fmt(o.insertion.depth_mm * 1e3) +
                    " um, axis " + fmt(o.insertion.angle_deg) + " deg -> " + o.result);
    o.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return o;
  };
  if (strategy == Strategy::ProprioIC1 || strategy == Strategy::ProprioIC2) {
    o.log.push_back(std::string("proprioception only, ") +
                    (strategy == Strategy::ProprioIC1 ? "IC1" : "IC2") +
                    ": reach the recorded insertion pose from start " + std::to_string(start + 1));
    return finish(move(c, q, su.p_ins, q_ref, s.motion, rep, g));
  }
  // Laser feedback: approach (IC2), then scan, register, correct, verify; finally insert.
  Pose approach = cs.T_target_part_insert;
  approach.translation() = cs.approach_mm;
  Pose part =
      move(c, q, c.flange_for_part(su.T_world_target_believed * approach), q_ref, s.motion, rep, g);
  o.log.push_back("approach with IC2 from start " + std::to_string(start + 1));
  const bool orient = strategy == Strategy::LaserPose;
  Measurement m;
  std::optional<Pose> tracked;       // the target's last trusted measurement (scan frame)
  std::optional<Pose> tracked_part;  // the part relative to the target: last measured, then moved
  auto refuse = [&](const std::string& why) {
    o.result = "refused: " + why;
    o.log.push_back(o.result);
    o.insertion = cell::check_insertion(cs, su.T_world_target, part);
    o.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return o;  // never insert blind
  };
  // Moves the part by `v` (scan / world frame) holding the elbow: a null-space drift toward IC2
  // would move the true flange by the model error while the nominal one stays put.
  auto shift = [&](const Pose& delta, double min_duration_s) {
    robot::MotionSettings ms = s.motion;
    ms.min_duration_s = min_duration_s;
    const robot::Joints hold = q;
    const Pose& B = c.T_world_baseA_believed;
    part = move(c, q, B.inverse() * delta * B * c.nominal.fk(q), hold, ms, rep, g);
    if (tracked_part)
      tracked_part = m.T_scan_target.inverse() * delta * m.T_scan_target * *tracked_part;
  };
  // Waypoints from the approach toward the insertion, each reached and verified by scans: an
  // unverified move of d mm on an arm whose model is off by a few degrees lands d * sin(error)
  // off, so the last unverified step is kept short.
  std::vector<double> fractions = {0.0};
  fractions.insert(fractions.end(), cs.stages.begin(), cs.stages.end());
  Pose way = approach;
  for (size_t w = 0; w < fractions.size(); ++w) {
    Pose next = approach;
    next.translation() =
        cs.T_target_part_insert.translation() +
        (cs.approach_mm - cs.T_target_part_insert.translation()) * (1 - fractions[w]);
    if (w > 0) {
      Pose d = Pose::Identity();
      d.translation() = m.T_scan_target.linear() * (next.translation() - way.translation());
      shift(d, s.motion.min_duration_s);
      o.log.push_back("stage " + std::to_string(w) + ": " + fmt(100 * fractions[w]) +
                      " % of the way in");
    }
    way = next;
    const Pose& Q = cs.T_target_part_insert;
    const bool outside =
        (way.translation() - Q.translation()).dot(Q.linear().col(2)) < -cs.clearance.depth_mm;
    const bool gated = w > 0;  // the approach has been corrected: the axial trust region applies
    for (int round = 0; round <= s.max_rounds; ++round, ++o.rounds) {
      m = Measurement{};
      Correction corr;
      double sweep_mm = 0;  // the scene's
      bool raised = false;
      for (int k = 0; k < s.max_scans && !m.ok; ++k) {  // scan until the registrations are trusted
        const uint64_t scan_seed = mix_seed(seed ^ (uint64_t(o.scans) << 32));
        const PointCloud scan = scan_cell(c, su, part, scan_seed, g, sweep_mm, raised);
        ++o.scans;
        if (!s.dump_dir.empty()) {
          const std::string tag = "_s" + std::to_string(su.setting);
          io::write_cloud(s.dump_dir + "/" + strategy_name(strategy) + tag + "_start" +
                              std::to_string(start + 1) + "_scan" + std::to_string(o.scans) +
                              ".pcd",
                          scan);
          io::write_cloud(s.dump_dir + "/target_ref" + tag + ".pcd", su.target_ref);
          io::write_cloud(s.dump_dir + "/part_ref" + tag + ".pcd", su.part_ref);
        }
        m = measure(scan, su.target_ref, su.part_ref, su.T_world_target_believed,
                    c.part_believed(q), cs, s, scan_seed, o.log, tracked, tracked_part);
        if (m.target_ok) tracked = m.T_scan_target;
        // The target was seen but not the part: the approach may have left it outside the sweep,
        // and then (not in the long sweep either) nearer to the scanner than its measuring range.
        const std::string not_found =
            "no trusted " + cs.scene.objects[cs.part].name + " near the target: next scan ";
        if (m.target_ok && !m.ok && sweep_mm == 0 && cs.search_sweep_mm > 0) {
          sweep_mm = cs.search_sweep_mm;
          o.log.push_back(not_found + "sweeps " + fmt(sweep_mm) + " mm");
        } else if (m.target_ok && !m.ok && !raised && cs.search_raise_mm > 0) {
          raised = true;
          o.log.push_back(not_found + "from " + fmt(cs.search_raise_mm) + " mm farther back");
        }
        if (!m.ok) continue;
        // The pose strategy corrects the orientation in the first round, the position after.
        // Along its axis the part is corrected while its end is still outside the target (above
        // the mouth): an IC2 approach leaves millimetres there, and each unverified move of d mm
        // lands ~0.1 d off. Inside, the target hides the end and the measured end is short.
        corr = compute_correction(m, way, orient && o.rounds == 0, outside);
        if (gated && std::abs(corr.axial_mm) > s.axial_gate_mm && k + 1 < s.max_scans) {
          m.ok = false;  // a thread end cut short or lengthened by the needle under it: look again
          o.log.push_back("implausible: " + fmt(corr.axial_mm * 1e3) +
                          " um along the axis after a verified move; re-scan");
        } else {
          tracked_part = m.T_scan_target.inverse() * m.T_scan_part;
        }
      }
      if (!m.ok) return refuse(m.reason + " after " + std::to_string(s.max_scans) + " scans");
      {  // What the simulation knows and the controller does not: the true error, for the log only.
        const Pose goal = su.T_world_target * way;
        const Eigen::Vector3d e = goal.translation() - part.translation(), n = goal.linear().col(2);
        o.log.push_back("  truth (simulation only): lateral error " +
                        fmt((e - n * n.dot(e)).norm() * 1e3) + " um, along the axis " +
                        fmt(n.dot(e) * 1e3) + " um");
      }
      o.log.push_back("round " + std::to_string(o.rounds + 1) + ": measured lateral error " +
                      fmt(corr.lateral_mm * 1e3) + " um, along the axis " +
                      fmt(corr.axial_mm * 1e3) + " um, axis " + fmt(corr.angle_deg) + " deg");
      const bool settled = corr.lateral_mm < s.verify_mm &&
                           std::abs(corr.axial_mm) < s.verify_axial_mm &&
                           (!orient || corr.angle_deg < cs.clearance.angle_deg / 2);
      if (settled && (round > 0 || w > 0)) break;
      // Correct, in the last round too: its reading is still the best estimate (applied
      // unverified, like a stage move). Along the axis at most the trust region once gated.
      const Correction step = gated ? limit_axial(corr, s.axial_gate_mm) : corr;
      const planning::Trajectory tr = plan(c, c.nominal.fk(q), step.delta, s);
      if (!tr.ok) return refuse(tr.reason);
      shift(step.delta, tr.duration_s);
      o.log.push_back("corrected: " + fmt(tr.translation_mm * 1e3) + " um, " +
                      fmt(tr.rotation_deg) + " deg in " + fmt(tr.duration_s) + " s" +
                      (round == s.max_rounds ? " (last round, unverified)" : ""));
      if (round == s.max_rounds) break;
    }
  }
  // Insert: the last step, along the measured target.
  Pose d = Pose::Identity();
  d.translation() =
      m.T_scan_target.linear() * (cs.T_target_part_insert.translation() - way.translation());
  shift(d, s.motion.min_duration_s);
  return finish(part);
}

io::Json outcome_json(const Outcome& o) {
  return {{"strategy", strategy_name(o.strategy)},
          {"setting", o.setting},
          {"start", o.start + 1},
          {"seed", o.seed},
          {"success", o.success},
          {"result", o.result},
          {"lateral_um", {o.insertion.x_mm * 1e3, o.insertion.y_mm * 1e3}},
          {"angle_deg", o.insertion.angle_deg},
          {"depth_um", o.insertion.depth_mm * 1e3},
          {"scans", o.scans},
          {"rounds", o.rounds},
          {"time_s", o.time_s},
          {"log", o.log}};
}

}  // namespace laserfit::controller
