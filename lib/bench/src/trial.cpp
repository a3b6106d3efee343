// Trials: conditions -> scene -> scan (simulated, or read back from a dataset) -> ground truth.
#include <algorithm>
#include <sstream>

#include "laserfit/bench/recorded.hpp"
#include "laserfit/bench/trial.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "laserfit/scan/reference.hpp"

namespace laserfit::bench {

namespace {

uint64_t trial_seed(uint64_t benchmark_seed, uint64_t n) {
  return mix_seed(mix_seed(benchmark_seed) ^ (0x5eed0000ull + n));
}

// One trial per recorded scan. Its seed derives from the image id, so a simulated benchmark
// exported as recorded scenes (image id = trial index) registers with the same seeds.
void append_recorded(const Benchmark& b, int scene, std::vector<Trial>& trials) {
  int r = 0;
  for (const auto& [image, objects] : b.scenes[scene].truth) {
    Trial t;
    t.index = int(trials.size()), t.scene = scene, t.repetition = r++, t.image = image;
    t.seed = trial_seed(b.seed, uint64_t(image));
    t.conditions.rotation_deg = t.conditions.translation_mm = -1;  // measured, not perturbed
    trials.push_back(t);
  }
}

}  // namespace

std::vector<Trial> enumerate_trials(const Benchmark& b) {
  // Grid cells: the cartesian product of the axes' values, in axis_names() order.
  std::vector<Conditions> cells(1);
  if (b.mode == Sampling::Grid)
    for (const auto& name : axis_names()) {
      const auto it = b.axes.find(name);
      if (it == b.axes.end()) continue;
      std::vector<Conditions> next;
      for (const auto& c : cells)
        for (double v : it->second) {
          Conditions d = c;
          axis(d, name) = v;
          next.push_back(d);
        }
      cells = next;
    }
  std::vector<Trial> trials;
  for (size_t s = 0; s < b.scenes.size(); ++s) {
    if (b.scenes[s].recorded()) {
      append_recorded(b, int(s), trials);
      continue;
    }
    for (size_t c = 0; c < cells.size(); ++c)
      for (int r = 0; r < b.trials; ++r) {
        Trial t;
        t.index = int(trials.size()), t.scene = int(s), t.cell = int(c), t.repetition = r;
        t.seed = trial_seed(b.seed, uint64_t(t.index));
        t.conditions = cells[c];
        if (b.mode == Sampling::Random) {
          Mt19937_64 g = block_rng(b.seed, 2000 + s, uint64_t(r));
          for (const auto& [name, range] : b.axes)
            axis(t.conditions, name) =
                range.size() == 1 ? range[0] : range[0] + uniform01(g) * (range[1] - range[0]);
        }
        trials.push_back(t);
      }
  }
  return trials;
}

std::vector<Trial> select_trials(const Benchmark& b, const std::vector<int>& repetitions,
                                 const std::vector<std::string>& scenes) {
  const auto wanted = scene_indices(b, scenes);
  std::vector<Trial> out;
  for (const auto& t : enumerate_trials(b))
    if ((repetitions.empty() || std::count(repetitions.begin(), repetitions.end(), t.repetition)) &&
        std::count(wanted.begin(), wanted.end(), t.scene))
      out.push_back(t);
  return out;
}

Shard parse_shard(const std::string& text) {
  Shard s;
  char slash = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> s.i >> slash >> s.n) || slash != '/' || (in >> extra) || s.n < 1 || s.i < 0 ||
      s.i >= s.n)
    throw Error("--shard '" + text + "': expected i/N with 0 <= i < N");
  return s;
}

namespace {

// `nominal` rotated by up to `deg` about a uniform random axis through `pivot` (object frame) and
// moved up to `mm` (uniform in a ball); angle uniform in [0, deg]. About `fixed` (the scene's
// frame) instead when given, by an angle uniform in [-deg, deg]; the random axis is drawn all the
// same, so the translations are those of the uniform draws. The pivot's point of the object ends
// within `mm` of its nominal place.
Pose perturbed(const Pose& nominal, double deg, double mm, Mt19937_64& g,
               const Eigen::Vector3d& pivot = Eigen::Vector3d::Zero(),
               const std::optional<Eigen::Vector3d>& fixed = std::nullopt) {
  auto unit_ball = [&] {
    Eigen::Vector3d v;
    do {  // z, y, x: GCC's argument order, as recorded; sequenced for any compiler
      for (int i = 2; i >= 0; --i) v[i] = uniform01(g) * 2 - 1;
    } while (v.squaredNorm() > 1 || v.squaredNorm() < 1e-6);
    return v;
  };
  const Eigen::Vector3d drawn = unit_ball().normalized();
  const double u = uniform01(g);
  const Eigen::Vector3d axis = fixed ? (nominal.rotation().transpose() * *fixed).eval() : drawn;
  const double angle = (fixed ? 2 * u - 1 : u) * std::max(0.0, deg) * M_PI / 180;
  const Eigen::Vector3d t = unit_ball() * std::max(0.0, mm);
  Pose T = nominal;
  T.linear() = nominal.rotation() * Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  T.translation() = nominal * pivot + t - T.linear() * pivot;
  return T;
}

}  // namespace

PreparedScene prepare_scene(const Benchmark& b, int scene) {
  const auto& sc = b.scenes[scene];
  if (sc.recorded()) return prepare_recorded(sc, b.seed);
  PreparedScene p;
  p.scene = scan::load_scene(sc.scene_path);
  for (const auto& t : sc.targets) {
    int idx = -1;
    for (size_t i = 0; i < p.scene.objects.size(); ++i)
      if (p.scene.objects[i].name == t.object) idx = int(i);
    if (idx < 0)
      throw Error(b.file, "scene '" + sc.name + "' has no object named '" + t.object + "'");
    const auto& o = p.scene.objects[idx];
    // A wrong-object trial registers another part's CAD where this object is.
    const TriMesh mesh = t.reference_mesh.empty() ? o.mesh : cad::import_cad(t.reference_mesh).mesh;
    if (t.reference == ReferenceSource::Full) {
      sampling::SamplingSettings ss;
      ss.count = t.reference_points;
      ss.seed = b.seed;
      p.reference.push_back(sampling::sample_uniform(mesh, ss));
    } else {  // what the nominal sweep sees of the nominally placed object
      p.reference.push_back(scan::view_reference(mesh, o.T_base_object, p.scene.settings,
                                                 t.reference_points, b.seed));
    }
    p.reference_mesh.push_back(mesh);
    p.object.push_back(idx);
    p.model.push_back(o.mesh.vertices);
    Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
    if (t.pivot == Pivot::View) {  // the seen part of the object's own mesh, whatever the reference
      const PointCloud seen =
          t.reference == ReferenceSource::View && t.reference_mesh.empty()
              ? p.reference.back()
              : scan::view_reference(o.mesh, o.T_base_object, p.scene.settings, 20000, b.seed);
      if (seen.points.empty())
        throw Error(b.file, "pivot: view: the nominal sweep sees nothing of '" + t.object + "'");
      for (const auto& q : seen.points) pivot += q.cast<double>();
      pivot /= double(seen.points.size());
    } else if (t.pivot == Pivot::Centre) {  // of the mesh's bounding box: a part turned in place
      pivot = o.mesh.bbox().center().cast<double>();
    }
    p.pivot.push_back(pivot);
  }
  return p;
}

TrialInput simulate_trial(const Benchmark& b, const PreparedScene& p, const Trial& t) {
  const Conditions& c = t.conditions;
  scan::ScanScene s = p.scene;
  s.seed = t.seed;
  auto& n = s.settings.noise;
  n.depth_sigma_um *= c.noise_scale, n.x_jitter_um *= c.noise_scale;
  n.speckle_sigma_um *= c.noise_scale, n.bias_sigma_um *= c.noise_scale;
  if (c.outlier_rate >= 0) {  // outliers on every surface, not only the shiny ones
    n.outlier_rate = c.outlier_rate;
    for (auto& o : s.objects) o.shiny = true;
  }
  auto& sw = s.settings.sweep;  // shorten the sweep about its centre
  Pose shift = Pose::Identity();
  shift.translation() = sw.direction * (0.5 * (1 - c.sweep_fraction) * sw.length_mm);
  sw.T_base_sensor_start = sw.T_base_sensor_start * shift;
  sw.length_mm *= c.sweep_fraction;
  // Pose draws depend on (scene, repetition) only: every grid cell sees the same poses, so a
  // curve over an axis compares like with like (a paired design).
  Mt19937_64 g = block_rng(b.seed, 1000 + uint64_t(t.scene), uint64_t(t.repetition));
  std::vector<Pose> nominal;
  for (size_t k = 0; k < p.object.size(); ++k) {
    Pose& T = s.objects[p.object[k]].T_base_object;
    nominal.push_back(T);
    T = perturbed(T, c.rotation_deg, c.translation_mm, g, p.pivot[k],
                  b.scenes[t.scene].targets[k].turn_about);
  }
  const scan::ScanResult r = scan::simulate_scan(s);
  TrialInput in;
  in.scan = r.cloud;
  in.scan_seed = r.seed;
  in.scan_points = r.stats.valid;
  in.has_prior = b.scenes[t.scene].use_prior;
  for (size_t k = 0; k < p.object.size(); ++k) {
    in.truth.push_back(r.T_scan_object[p.object[k]]);
    in.prior.push_back(
        c.prior_rotation_deg < 0 && c.prior_translation_mm < 0
            ? nominal[k]
            : perturbed(in.truth.back(), c.prior_rotation_deg, c.prior_translation_mm, g));
  }
  return in;
}

TrialInput trial_input(const Benchmark& b, const PreparedScene& p, const Trial& t) {
  const SceneCase& sc = b.scenes[t.scene];
  return sc.recorded() ? recorded_trial(sc, p, t) : simulate_trial(b, p, t);
}

io::Json input_json(const Benchmark& b, const PreparedScene& p, const Trial& t,
                    const TrialInput& in) {
  io::Json cond = io::Json::object(), targets = io::Json::array();
  for (const auto& name : axis_names()) cond[name] = axis(t.conditions, name);
  const auto& sc = b.scenes[t.scene];
  for (size_t k = 0; k < in.truth.size(); ++k) {
    targets.push_back({{"object", sc.targets[k].object},
                       {"label", p.object[k]},  // scan label of its points
                       {"reference", "refs/" + sc.name + "_" + sc.targets[k].object + ".pcd"},
                       {"symmetry", sc.targets[k].symmetry.describe()},
                       {"pivot", name_of(sc.targets[k].pivot)},
                       {"pivot_mm", {p.pivot[k].x(), p.pivot[k].y(), p.pivot[k].z()}},
                       {"voxel_mm", sc.targets[k].voxel_mm},
                       {"expect", sc.targets[k].expect_failure ? "failure" : "pose"},
                       {"T_scan_object", io::pose_to_json(in.truth[k])}});
    if (in.has_prior) targets.back()["prior"] = io::pose_to_json(in.prior[k]);  // none: global
  }
  return {{"benchmark", b.name},        {"trial", t.index},
          {"scene", sc.name},           {"cell", t.cell},
          {"repetition", t.repetition}, {"seed", t.seed},
          {"scan_seed", in.scan_seed},  {"scan_points", in.scan_points},
          {"conditions", cond},         {"targets", targets}};
}

TrialInput read_trial(const PreparedScene& p, const std::string& scan_pcd,
                      const std::string& gt_json) {
  TrialInput in;
  in.scan = io::read_cloud(scan_pcd);
  const io::Json j = io::read_json(gt_json);
  try {
    in.scan_seed = j.at("scan_seed").get<uint64_t>();
    in.scan_points = j.at("scan_points").get<size_t>();
    const auto& targets = j.at("targets");
    if (targets.size() != p.object.size()) throw Error("target count differs from the benchmark");
    in.has_prior = !targets.empty() && targets[0].contains("prior");
    for (const auto& t : targets) {
      in.truth.push_back(io::pose_from_json(t.at("T_scan_object"), gt_json));
      in.prior.push_back(in.has_prior ? io::pose_from_json(t.at("prior"), gt_json)
                                      : Pose::Identity());
    }
  } catch (const io::Json::exception& e) {
    throw Error(gt_json, std::string("not a laserfit ground-truth file: ") + e.what());
  } catch (const Error& e) {
    throw Error(gt_json, e.what());
  }
  return in;
}

}  // namespace laserfit::bench
