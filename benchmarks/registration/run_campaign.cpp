// registration_campaign <campaign.yaml> [--methods a,b] [--trials N] [--jobs J] [--out DIR]
//                       [--dump DIR --dump-trials N]
// Runs the registration accuracy campaign and writes one JSON line per (trial, target, method)
// to DIR/results.jsonl (atomically). --dump writes the target's scan points, the reference and the
// ground truth of the first trials for the Open3D comparison (benchmarks/registration/open3d_baseline.py).
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include "campaign.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/sampling/sampling.hpp"

using namespace laserfit;
namespace fs = std::filesystem;

namespace {

struct Prepared {
  int object = -1;
  PointCloud ref;
  std::vector<Eigen::Vector3f> model;  // mesh vertices, for MSSD
};

Pose mid_sweep(const scan::ScanSettings& s) {
  Pose step = Pose::Identity();
  step.translation() = s.sweep.direction * (0.5 * s.sweep.length_mm);
  return s.sweep.T_base_sensor_start * step;
}

Prepared prepare(const scan::ScanScene& scene, const campaign::Target& t, uint64_t seed) {
  Prepared p;
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].name == t.object) p.object = int(i);
  if (p.object < 0) throw Error(scene.file, "no object named '" + t.object + "'");
  const auto& o = scene.objects[p.object];
  sampling::SamplingSettings ss;
  ss.count = t.reference_points;
  ss.seed = seed;
  if (t.reference == "full") {
    p.ref = sampling::sample_uniform(o.mesh, ss);
  } else {  // what the nominal sweep sees of the nominally placed object
    sampling::ViewSettings v;
    v.T_mesh_sensor.push_back(o.T_base_object.inverse() * mid_sweep(scene.settings));
    v.geometry = scene.settings.sensor;
    p.ref = sampling::sample_visible(o.mesh, v, ss);
  }
  p.model = o.mesh.vertices;
  return p;
}

Pose perturbed(const Pose& nominal, const campaign::Campaign& c, std::mt19937_64& g) {
  // Rotation: uniform axis, angle uniform in [0, rotation_deg]; translation uniform in a ball.
  auto unit = [&] {
    Eigen::Vector3d v;
    do v = Eigen::Vector3d(uniform01(g), uniform01(g), uniform01(g)) * 2 - Eigen::Vector3d::Ones();
    while (v.squaredNorm() > 1 || v.squaredNorm() < 1e-6);
    return v;
  };
  const Eigen::Vector3d axis = unit().normalized();
  const double angle = uniform01(g) * c.rotation_deg * M_PI / 180;
  const Eigen::Vector3d t = unit() * c.translation_mm;
  Pose T = nominal;
  T.linear() = nominal.rotation() * Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  T.translation() += t;
  return T;
}

Eigen::Vector3d viewpoint_of(const PointCloud& scan) {
  std::istringstream in(scan.metadata.at("viewpoint"));
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

io::Json record_json(const campaign::Record& r) {
  return {{"scene", r.scene}, {"object", r.object}, {"method", r.method}, {"trial", r.trial},
          {"seed", r.seed}, {"status", r.status}, {"reason", r.reason}, {"t_err_um", r.t_err_mm * 1e3},
          {"r_err_deg", r.r_err_deg}, {"mssd_um", r.mssd_mm * 1e3}, {"time_s", r.time_s},
          {"scan_points", r.scan_points}, {"success", r.success}, {"false_accept", r.false_accept}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Registration accuracy campaign (simulated scans with ground truth)"};
  std::string file, methods = "ceres", out = "reports/registration", dump, only;
  int trials = 0, jobs = 1, dump_trials = 0;
  app.add_option("campaign", file, "campaign definition (YAML)")->required();
  app.add_option("--methods", methods, "comma-separated: paper, ceres, point_to_plane, point_to_point, gicp, ndt")->capture_default_str();
  app.add_option("--trials", trials, "override the number of trials per scene");
  app.add_option("--scenes", only, "comma-separated scene names to run (default all)");
  app.add_option("--jobs", jobs, "trials in parallel (1 = honest per-registration timing)")->capture_default_str();
  app.add_option("--out", out, "output directory (results.jsonl)")->capture_default_str();
  app.add_option("--dump", dump, "write target scans, references and ground truth here (Open3D baseline)");
  app.add_option("--dump-trials", dump_trials, "how many trials per scene to dump")->capture_default_str();
  bool full_scans = false;
  app.add_flag("--dump-full-scans", full_scans, "also dump each dumped trial's whole scan (large)");
  CLI11_PARSE(app, argc, argv);
  try {
    campaign::Campaign c = campaign::load_campaign(file);
    if (trials > 0) c.trials = trials;
    std::vector<std::string> ms;
    for (std::stringstream in(methods); std::getline(in, methods, ',');) ms.push_back(methods);
    if (!dump.empty()) fs::create_directories(dump);
    std::vector<io::Json> lines;
    io::Json manifest = io::Json::array();
    for (size_t si = 0; si < c.scenes.size(); ++si) {
      const auto& sc = c.scenes[si];
      if (!only.empty() && ("," + only + ",").find("," + sc.name + ",") == std::string::npos) continue;
      const scan::ScanScene scene = scan::load_scene(sc.scene_path);
      std::vector<Prepared> prep;
      for (const auto& t : sc.targets) prep.push_back(prepare(scene, t, c.seed));
      if (!dump.empty())
        for (size_t k = 0; k < prep.size(); ++k) io::write_cloud(dump + "/" + sc.name + "_" + sc.targets[k].object + "_ref.pcd", prep[k].ref);
      std::vector<std::vector<campaign::Record>> recs(c.trials);
      std::vector<io::Json> dumps(c.trials, io::Json::array());
      std::atomic<int> next{0}, done{0};
      std::mutex err_m;
      std::string first_error;
      auto worker = [&] {
        for (int i; (i = next++) < c.trials;) {
          try {
            std::mt19937_64 g = block_rng(c.seed, 1000 + si, uint64_t(i));
            scan::ScanScene s = scene;
            s.seed = g();
            std::vector<Pose> nominal;
            for (size_t k = 0; k < prep.size(); ++k) {
              auto& o = s.objects[prep[k].object];
              nominal.push_back(o.T_base_object);
              o.T_base_object = perturbed(o.T_base_object, c, g);
            }
            const scan::ScanResult scan = scan::simulate_scan(s);
            for (size_t k = 0; k < prep.size(); ++k) {
              const auto& tg = sc.targets[k];
              const Pose& gt = scan.T_scan_object[prep[k].object];
              if (i < dump_trials) {
                PointCloud mine;
                size_t n = 0;
                for (size_t j = 0; j < scan.cloud.size(); ++j) n += scan.cloud.labels[j] == prep[k].object;
                const size_t stride = std::max<size_t>(1, n / 300000 + 1);
                for (size_t j = 0, m = 0; j < scan.cloud.size(); ++j)
                  if (scan.cloud.labels[j] == prep[k].object && m++ % stride == 0) mine.points.push_back(scan.cloud.points[j]);
                mine.width = int(mine.points.size());
                const std::string f = sc.name + "_" + tg.object + "_" + std::to_string(i) + ".pcd";
                io::write_cloud(dump + "/" + f, mine);
                if (k == 0 && full_scans) io::write_cloud(dump + "/" + sc.name + "_scan_" + std::to_string(i) + ".pcd", scan.cloud);
                dumps[i].push_back({{"scene", sc.name}, {"object", tg.object}, {"trial", i}, {"scan", f},
                                    {"ref", sc.name + "_" + tg.object + "_ref.pcd"}, {"T_gt", io::pose_to_json(gt)},
                                    {"q0", io::pose_to_json(nominal[k])}, {"symmetry", tg.symmetry.describe()},
                                    {"voxel_mm", tg.voxel_mm}});
              }
              for (const auto& m : ms) {
                auto rs = campaign::method_settings(m);
                rs.pre.voxel_mm = tg.voxel_mm;
                rs.q0 = Eigen::Quaterniond(nominal[k].rotation());
                if (m != "paper") rs.prior = nominal[k];
                rs.pre.use_viewpoint = true, rs.pre.viewpoint = viewpoint_of(scan.cloud);
                rs.seed = scan.seed;
                campaign::Record r;
                r.scene = sc.name, r.object = tg.object, r.method = m;
                r.trial = i, r.seed = scan.seed, r.scan_points = scan.stats.valid;
                const auto t0 = std::chrono::steady_clock::now();
                // Two candidate parts: the points near the prior-placed reference, then the
                // cluster nearest it (the CLI default tries four).
                registration::RegistrationResult res;
                try {
                  res = registration::register_segmented(scan.cloud, prep[k].ref, rs, 2);
                } catch (const Error& e) {  // unusable scan for this target: a failure, recorded
                  res.status = registration::Status::Failed;
                  res.reason = std::string("error: ") + e.what();
                }
                r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                r.status = registration::status_name(res.status), r.reason = res.reason;
                const auto e = metrics::pose_error(res.T_scan_ref, gt, tg.symmetry, prep[k].model);
                r.t_err_mm = e.t_mm, r.r_err_deg = e.r_deg, r.mssd_mm = e.mssd_mm;
                const bool within = e.t_mm <= c.t_tol_mm && e.r_deg <= c.r_tol_deg;
                const bool sym_ok = res.status == registration::Status::Ambiguous &&
                                    tg.symmetry.kind == metrics::Symmetry::Kind::Continuous;
                r.success = within && (res.status == registration::Status::Ok || sym_ok);
                r.false_accept = res.status == registration::Status::Ok && !within;
                recs[i].push_back(r);
              }
            }
            const int d = ++done;
            std::cerr << "\r" << sc.name << ": " << d << "/" << c.trials << " trials" << std::flush;
          } catch (const std::exception& e) {
            std::lock_guard<std::mutex> l(err_m);
            if (first_error.empty()) first_error = e.what();
          }
        }
      };
      std::vector<std::thread> pool;
      for (int j = 0; j < std::max(1, jobs); ++j) pool.emplace_back(worker);
      for (auto& t : pool) t.join();
      std::cerr << "\n";
      if (!first_error.empty()) throw Error(sc.scene_path, first_error);
      for (int i = 0; i < c.trials; ++i) {
        for (const auto& r : recs[i]) lines.push_back(record_json(r));
        for (const auto& d : dumps[i]) manifest.push_back(d);
      }
    }
    fs::create_directories(out);
    std::string text;
    for (const auto& l : lines) text += l.dump() + "\n";
    write_file_atomic(out + "/results.jsonl", text);
    if (!dump.empty()) write_file_atomic(dump + "/manifest.json", manifest.dump(1));
    std::cerr << "wrote " << lines.size() << " records to " << out << "/results.jsonl\n";
  } catch (const std::exception& e) {
    std::cerr << "registration_campaign: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
