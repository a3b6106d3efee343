// Preparing a test setting: teach the insertion on the true arm near IC1 (as an operator would,
// by hand), record what the robot believes, choose the start configurations and the scan pose.
#include <Eigen/Geometry>

#include "laserfit/controller/sim.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/robot/ik.hpp"
#include "laserfit/scan/reference.hpp"

namespace laserfit::controller {
namespace {

robot::Joints ik_or_throw(const robot::ArmModel& arm, const Pose& T, const robot::Joints& hint,
                          const std::string& what) {
  robot::IkSettings ik;
  ik.use_q_ref = true, ik.q_ref = hint, ik.max_iterations = 3000;
  const auto r = robot::solve_ik(arm, T, hint, ik);
  if (!r.converged || !r.within_limits)
    throw Error(what + ": not reachable (" + std::to_string(r.error_mm) + " mm off" +
                (r.within_limits ? "" : ", joint limits") + ")");
  return r.q;
}

}  // namespace

SimSetup prepare_setting(const cell::Cell& c, int k, const ControllerSettings& s, uint64_t seed) {
  const auto& cs = c.s;
  SimSetup su;
  su.setting = k;
  su.T_world_target = cs.target_poses.at(k);
  // Teaching: the operator guides the true arm until the part sits in the target.
  const Pose part_at_insert = su.T_world_target * cs.T_target_part_insert;
  const Pose flange_true =
      c.T_world_baseA_true.inverse() * part_at_insert * c.T_flange_part_true.inverse();
  su.q_taught = ik_or_throw(c.trueA, flange_true, cs.q_teach_hint,
                            cs.file + ": setting " + std::to_string(k) + " insertion");
  su.p_ins = c.nominal.fk(su.q_taught);  // what the robot records
  su.T_world_target_believed =
      c.T_world_baseA_believed * su.p_ins * cs.T_flange_part * cs.T_target_part_insert.inverse();
  su.q_ic2_ref = su.q_taught;
  su.q_ic2_ref[0] += cs.ic2_joint1_deg * M_PI / 180;
  // Start configurations: the i-th is i * step from the insertion pose (up and aside, seeded).
  Mt19937_64 g = block_rng(seed, 0x57A87, uint64_t(k));
  for (int i = 1; i <= cs.start_configs; ++i) {
    const double dy = 2 * uniform01(g) - 1;  // drawn first: GCC's argument order, as recorded
    const double dx = 2 * uniform01(g) - 1;
    const Eigen::Vector3d dir(dx, dy, 1.0);
    Pose start = su.p_ins;
    start.translation() += dir.normalized() * (i * cs.start_step_mm);
    su.q_start.push_back(ik_or_throw(c.nominal, start, su.q_taught,
                                     cs.file + ": start configuration " + std::to_string(i)));
  }
  // The scan pose is taught too: the sensor placed where it sees the true target as the scene's
  // sweep does. The robot records its joints; what it believes about that pose is nominal fk.
  const auto& scene = cs.scene;
  const Pose scene_target = scene.objects[cs.target].T_base_object;
  const Pose sensor_true =
      su.T_world_target * scene_target.inverse() * scene.settings.sweep.T_base_sensor_start;
  su.q_scan = ik_or_throw(c.trueS, sensor_true * c.T_flange_sensor_true.inverse(), cs.q_sense_hint,
                          cs.file + ": scan pose of setting " + std::to_string(k));
  su.T_world_sensor_start = c.nominal.fk(su.q_scan) * cs.T_flange_sensor;
  // The raised search pose is commanded, not taught: the nominal model's IK of the scan pose moved
  // back along the view axis, so the true sensor lands there with the arm's model error.
  su.q_scan_raised = su.q_scan, su.T_world_sensor_raised = su.T_world_sensor_start;
  if (cs.search_raise_mm > 0) {
    const Pose raised = su.T_world_sensor_start * Eigen::Translation3d(0, 0, -cs.search_raise_mm);
    su.q_scan_raised = ik_or_throw(c.nominal, raised * cs.T_flange_sensor.inverse(), su.q_scan,
                                   cs.file + ": raised scan pose of setting " + std::to_string(k));
    su.T_world_sensor_raised = c.nominal.fk(su.q_scan_raised) * cs.T_flange_sensor;
  }
  // References: what the scene's sweep sees of the target and of the part at its approach pose
  // (the designed geometry; the arms' beliefs do not enter).
  Pose approach = cs.T_target_part_insert;
  approach.translation() = cs.approach_mm;
  su.target_ref = scan::view_reference(scene.objects[cs.target].mesh, scene_target, scene.settings,
                                       s.reference_points, seed);
  su.part_ref = scan::view_reference(scene.objects[cs.part].mesh, scene_target * approach,
                                     scene.settings, s.reference_points, seed + 1);
  return su;
}

TrialPlan plan_trial(const cell::CellSettings& cs, uint64_t seed, int i) {
  const int S = int(cs.target_poses.size());
  TrialPlan t;
  t.trial = i, t.robot = i / (S * cs.start_configs), t.setting = i % S;
  t.start = (i / S) % cs.start_configs;
  t.seed = mix_seed(seed ^ (uint64_t(i) << 8));
  return t;
}

void Campaign::prepare(const TrialPlan& t) {
  if (!cells_.count(t.robot))
    cells_.emplace(t.robot, std::make_unique<cell::Cell>(cs_, mix_seed(seed_) + t.robot));
  if (!setups_.count({t.robot, t.setting}))
    setups_.emplace(std::make_pair(t.robot, t.setting),
                    prepare_setting(*cells_[t.robot], t.setting, s_, seed_ + t.robot));
}

SweepRequest sweep_request(const cell::Cell& c, const SimSetup& su, double sweep_mm, bool raised) {
  const auto& sw = c.s.scene.settings.sweep;
  SweepRequest r;
  r.q_start = raised ? su.q_scan_raised : su.q_scan;
  r.direction = sw.direction, r.length_mm = sw.length_mm, r.speed_mm_s = sw.speed_mm_s;
  // A longer sweep starts earlier by half the extra length: the same straight motion of the
  // sensing arm, whose (linear, mm-short) error the sweep model already neglects.
  if (sweep_mm > sw.length_mm) r.lead_mm = (sweep_mm - sw.length_mm) / 2, r.length_mm = sweep_mm;
  return r;
}

scan::ScanResult sweep_cell(const cell::Cell& c, const SimSetup& su, const Pose& T_world_part_true,
                            uint64_t seed, Mt19937_64& g, const SweepRequest& r) {
  const auto& cs = c.s;
  scan::ScanScene sc = cs.scene;
  sc.seed = seed;
  // The sensing arm's true sensor pose vs the one it believes: the scan is computed in the
  // believed frame, so the objects move by the difference.
  const Pose believed = c.nominal.fk(r.q_start) * cs.T_flange_sensor;
  const Pose T_true =
      robot::with_repeatability(c.trueS.fk(r.q_start), cs.arm_errors, g) * c.T_flange_sensor_true;
  const Pose to_believed = believed * T_true.inverse();
  auto& sw = sc.settings.sweep;
  sw.T_base_sensor_start = believed;
  if (r.lead_mm != 0)
    sw.T_base_sensor_start =
        sw.T_base_sensor_start * Eigen::Translation3d(-r.direction * r.lead_mm);
  sw.direction = r.direction, sw.length_mm = r.length_mm, sw.speed_mm_s = r.speed_mm_s;
  sc.settings.motion.offset_sigma_mm = 0,
  sc.settings.motion.offset_sigma_deg = 0;  // the arm model has them
  // Other objects of the scene stay where they are relative to the target.
  const Pose moved = su.T_world_target * cs.scene.objects[cs.target].T_base_object.inverse();
  for (auto& o : sc.objects) o.T_base_object = to_believed * moved * o.T_base_object;
  sc.objects[cs.part].T_base_object = to_believed * T_world_part_true;
  return scan::simulate_scan(sc);
}

PointCloud scan_cell(const cell::Cell& c, const SimSetup& su, const Pose& T_world_part_true,
                     uint64_t seed, Mt19937_64& g, double sweep_mm, bool raised) {
  return sweep_cell(c, su, T_world_part_true, seed, g, sweep_request(c, su, sweep_mm, raised))
      .cloud;
}

}  // namespace laserfit::controller
