// laserfit-controller correct --cell C --scan S.pcd --target-ref T.pcd --part-ref P.pcd
//   --ee-pose "x y z qw qx qy qz" --target-prior "..." --thresholds T.yaml -o traj.csv
#include <iostream>

#include "commands.hpp"
#include "laserfit/controller/controller.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/units.hpp"
#include "laserfit/io/cloud_io.hpp"

namespace laserfit::ctl {
namespace {

struct Options {
  std::string cell, scan, target_ref, part_ref, ee_pose, target_prior, thresholds, out;
  std::string unit = "mm";  // of the clouds that do not state one and of the two poses
  bool orientation = false, json = false;
  uint64_t seed = 1;
};

int run(const Options& o) {
  using namespace controller;
  const cell::CellSettings cs = cell::load_cell(o.cell);
  ControllerSettings s = settings_for(cs);
  s.thresholds = registration::load_thresholds(o.thresholds);
  const cell::Cell c(cs, 0);  // only the believed quantities are used here
  const Unit unit = parse_unit(o.unit);
  Pose flange = parse_pose(o.ee_pose, "--ee-pose");
  Pose target_prior = parse_pose(o.target_prior, "--target-prior");
  flange.translation() *= unit_to_mm(unit), target_prior.translation() *= unit_to_mm(unit);
  const PointCloud scan = io::read_cloud(o.scan, unit);
  std::vector<std::string> log;
  const Pose part_prior = c.part_believed_from_flange(flange);
  const Measurement m =
      measure(scan, io::read_cloud(o.target_ref, unit), io::read_cloud(o.part_ref, unit),
              target_prior, part_prior, cs, s, o.seed, log);
  if (!m.ok) throw Error(o.scan, "no correction: " + m.reason);
  // The trajectory starts at --ee-pose: a pose in another unit or frame would start it where the
  // arm is not, though the scan still finds the part (the nearest cluster).
  const double off_mm = (m.T_scan_part.translation() - part_prior.translation()).norm();
  if (off_mm > s.max_part_offset_mm)
    throw Error(o.scan, "no correction: the part is " + std::to_string(int(off_mm)) +
                            " mm from where --ee-pose puts it (more than " +
                            std::to_string(int(s.max_part_offset_mm)) +
                            " mm): another frame, unit or arm?");
  Pose approach = cs.T_target_part_insert;
  approach.translation() = cs.approach_mm;
  const Correction corr = compute_correction(m, approach, o.orientation);
  const planning::Trajectory tr = plan(c, flange, corr.delta, s);
  if (!tr.ok) throw Error(o.scan, "correction refused: " + tr.reason);
  planning::write_trajectory_csv(o.out, tr);
  io::Json j = {{"trajectory", o.out},
                {"samples", tr.samples.size()},
                {"duration_s", tr.duration_s},
                {"translation_um", tr.translation_mm * 1e3},
                {"rotation_deg", tr.rotation_deg},
                {"measured_lateral_um", corr.lateral_mm * 1e3},
                {"log", log}};
  if (o.json)
    std::cout << j.dump(2) << "\n";
  else
    std::cout << "correction of " << tr.translation_mm * 1e3 << " um / " << tr.rotation_deg
              << " deg over " << tr.duration_s << " s -> " << o.out << " (" << tr.samples.size()
              << " samples)\n";
  return 0;
}

}  // namespace

Command add_correct(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app =
      root.add_subcommand("correct",
                          "One correction from files: register the target and the part in a "
                          "scan, plan the corrective trajectory, write it as CSV");
  app->add_option("--cell", o->cell, "cell definition (frames, grasp, insertion geometry)")
      ->required();
  app->add_option("--scan", o->scan, "scan (.pcd/.ply), sensing arm's base frame, mm")->required();
  app->add_option("--target-ref", o->target_ref, "reference cloud of the target")->required();
  app->add_option("--part-ref", o->part_ref, "reference cloud of the part")->required();
  app->add_option("--ee-pose", o->ee_pose,
                  "assembling arm's flange pose 'x y z qw qx qy qz' in its base (mm)")
      ->required();
  app->add_option("--target-prior", o->target_prior,
                  "where the target is believed to be, 'x y z qw qx qy qz' in the scan frame")
      ->required();
  app->add_option("--thresholds", o->thresholds, "tuned registration thresholds (laserfit tune)")
      ->required();
  app->add_option("-o,--output,--out", o->out,
                  "trajectory CSV: t, x, y, z (mm), qw, qx, qy, qz in the assembling arm's base")
      ->required();
  app->add_flag("--orientation", o->orientation,
                "correct the orientation too (else position only, as in the paper)");
  app->add_option("--seed", o->seed, "RANSAC seed")->capture_default_str();
  tools::add_unit_option(
      *app, "--unit", o->unit,
      "unit of the clouds that do not state one (laserfit's say mm) and of --ee-pose "
      "and --target-prior; the trajectory is written in mm");
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::ctl
