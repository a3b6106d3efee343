// laserfit scan <scene.yaml> -o scan.pcd: synthetic laser line scan with ground truth.
#include <memory>
#include <optional>
#include <sstream>

#include "command.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/scan/ground_truth.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string scene, output, gt, raw, flange_poses, hand_eye = "0 0 0 1 0 0 0", noise = "on";
  std::optional<uint64_t> seed;
  bool json = false;
  int jobs = 0;
};

int run(const Options& o) {
  if (o.noise != "on" && o.noise != "off") throw Error("--noise must be 'on' or 'off'");
  scan::ScanScene sc = scan::load_scene(o.scene);
  if (o.seed) sc.seed = *o.seed;
  if (o.noise == "off") sc.settings.noise.enabled = sc.settings.motion.enabled = false;
  const scan::ScanResult r = scan::simulate_scan(sc);
  if (r.stats.valid == 0) {
    const auto& s = r.stats;
    throw Error(o.scene, "the scan saw nothing: of " + std::to_string(s.rays) + " rays " +
                             std::to_string(s.hits) + " hit an object, " +
                             std::to_string(s.out_of_range) + " out of range, " +
                             std::to_string(s.grazing) + " grazing, " +
                             std::to_string(s.camera_shadow) +
                             " camera shadow (check the sweep start pose)");
  }
  // Write every file to its temporary first; rename them only when all were written.
  std::vector<std::unique_ptr<AtomicFile>> files;
  files.push_back(std::make_unique<AtomicFile>(o.output));
  io::write_cloud(*files.back(), r.cloud);
  if (!o.raw.empty()) {
    files.push_back(std::make_unique<AtomicFile>(o.raw));
    io::write_cloud(*files.back(), r.raw);
  }
  if (!o.flange_poses
           .empty()) {  // what the arm logs: T_base_flange per profile, as assemble reads it
    const Pose T_flange_sensor = parse_pose(o.hand_eye, "--hand-eye");
    files.push_back(std::make_unique<AtomicFile>(o.flange_poses, false));
    files.back()->stream() << "# T_base_flange per profile (nominal): x y z qw qx qy qz, mm\n";
    for (const Pose& T_base_sensor : r.T_base_sensor_nominal)
      files.back()->stream() << pose_to_string(T_base_sensor * T_flange_sensor.inverse()) << "\n";
  }
  if (!o.gt.empty()) {
    files.push_back(std::make_unique<AtomicFile>(o.gt, false));
    files.back()->stream() << scan::ground_truth_json(sc, r).dump(1) << "\n";
  }
  for (auto& f : files) f->commit();

  const auto& s = r.stats;
  const double pts_per_s = double(s.rays) / r.timings.total_s;
  io::Json j{{"scene", o.scene},
             {"output", o.output},
             {"seed", sc.seed},
             {"noise", o.noise},
             {"width", r.cloud.width},
             {"height", r.cloud.height},
             {"valid_points", s.valid},
             {"rays", s.rays},
             {"hits", s.hits},
             {"lost",
              {{"out_of_range", s.out_of_range},
               {"grazing", s.grazing},
               {"camera_shadow", s.camera_shadow},
               {"dropouts", s.dropouts}}},
             {"artefacts", {{"outliers", s.outliers}, {"mixed_pixels", s.mixed_pixels}}},
             {"timings_s",
              {{"total", r.timings.total_s},
               {"bvh", r.timings.bvh_s},
               {"laser_cpu", r.timings.laser_s},
               {"camera_cpu", r.timings.camera_s},
               {"noise_cpu", r.timings.noise_s}}},
             {"points_per_s", pts_per_s}};
  std::ostringstream h;
  h << "scanned " << o.scene << " (seed " << sc.seed << ", noise " << o.noise
    << "): " << r.cloud.width << " x " << r.cloud.height << " profile points, " << s.valid
    << " valid\n"
    << "  lost: " << s.out_of_range << " out of range, " << s.grazing << " grazing, "
    << s.camera_shadow << " camera shadow, " << s.dropouts << " dropouts; " << s.outliers
    << " outliers, " << s.mixed_pixels << " mixed pixels\n"
    << "  " << r.timings.total_s << " s (" << pts_per_s / 1e6 << " M profile points/s)\n"
    << "  wrote " << o.output << (o.gt.empty() ? "" : ", " + o.gt)
    << (o.raw.empty() ? "" : ", " + o.raw) << (o.flange_poses.empty() ? "" : ", " + o.flange_poses)
    << "\n";
  emit(o.json, j, h.str());
  return 0;
}

}  // namespace

Command add_scan(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "scan",
      "Simulate a laser line scan (LLT3000-25 class) of a scene file: organized cloud in "
      "the base frame (NaN = no measurement), ground truth, optional raw profiles.");
  app->add_option("scene", o->scene, "scene file (YAML, mm); see datasets/scenes/")->required();
  app->add_option("-o,--output", o->output,
                  "scan cloud (.pcd or .ply): width 2048 x height profiles")
      ->required();
  app->add_option("--gt", o->gt, "ground-truth JSON (object and sensor poses, seed, settings)");
  app->add_option("--raw", o->raw,
                  "raw profiles in the sensor frame (x, 0, z) as a driver delivers them");
  app->add_option("--flange-poses", o->flange_poses,
                  "CSV of the flange pose per profile (nominal), as an arm would log it for "
                  "laserfit assemble with --raw's profiles");
  app->add_option("--hand-eye", o->hand_eye,
                  "T_flange_sensor 'x y z qw qx qy qz' for --flange-poses")
      ->capture_default_str();
  app->add_option("--seed", o->seed, "random seed (overrides the scene's)");
  app->add_option("--noise", o->noise, "on | off (off: ideal sensor and arm)")
      ->capture_default_str();
  add_jobs(*app, o->jobs);
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
