// laserfit bench export --bop: a simulated benchmark written as recorded scenes (BOP layout).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "laserfit/bench/recorded.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/parallel.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/mesh_writer.hpp"

namespace laserfit::bench {
namespace fs = std::filesystem;

namespace {

std::string axis_name(const Eigen::Vector3d& a) {
  int i = 0;
  a.cwiseAbs().maxCoeff(&i);
  return std::string(1, char('x' + i));
}

// BOP's models_info.json entry: diameter (the largest distance between two vertices, exact:
// O(n^2) over the vertices, seconds for 10^5), bounding box, and the symmetries in its form.
io::Json model_info(const TriMesh& mesh, const metrics::Symmetry& sym) {
  double d2 = 0;
  const auto& v = mesh.vertices;
  for (size_t i = 0; i < v.size(); ++i)
    for (size_t j = i + 1; j < v.size(); ++j)
      d2 = std::max(d2, double((v[i] - v[j]).squaredNorm()));
  const auto box = mesh.bbox();
  const Eigen::Vector3f size = box.sizes();
  io::Json j = {{"diameter", std::sqrt(d2)}, {"min_x", box.min().x()}, {"min_y", box.min().y()},
                {"min_z", box.min().z()},    {"size_x", size.x()},     {"size_y", size.y()},
                {"size_z", size.z()}};
  const Eigen::Vector3d a = sym.axis;
  if (sym.kind == metrics::Symmetry::Kind::Continuous)
    j["symmetries_continuous"] = {{{"axis", {a.x(), a.y(), a.z()}}, {"offset", {0, 0, 0}}}};
  if (sym.kind == metrics::Symmetry::Kind::Discrete) {
    io::Json list = io::Json::array();
    const auto rotations = sym.rotations();  // the identity first: BOP lists the others
    for (size_t k = 1; k < rotations.size(); ++k) {
      Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
      T.topLeftCorner<3, 3>() = rotations[k];
      std::vector<double> flat;
      for (int i = 0; i < 16; ++i) flat.push_back(T(i / 4, i % 4));
      list.push_back(flat);
    }
    j["symmetries_discrete"] = list;
  }
  return j;
}

// One target of the exported benchmark.yaml, in flow style.
std::string target_yaml(const Target& t, int obj_id, int label, const std::string& ref,
                        const std::string& model) {
  std::ostringstream y;
  y << "      - {object: " << t.object << ", obj_id: " << obj_id << ", label: " << label
    << ", reference_cloud: " << ref << ", model: " << model << ", symmetry: \""
    << t.symmetry.describe() << "\", voxel_mm: " << io::Json(t.voxel_mm).dump()
    << ", expect: " << (t.expect_failure ? "failure" : "pose");
  if (t.weak_rotation) y << ", weak_rotation: " << axis_name(*t.weak_rotation);
  if (t.weak_translation) y << ", weak_translation: " << axis_name(*t.weak_translation);
  y << "}\n";
  return y.str();
}

std::string six(int id) {
  char s[16];
  std::snprintf(s, sizeof s, "%06d", id);
  return s;
}

}  // namespace

namespace {

ExportSummary write_export(const Benchmark& b, const std::string& dir, const std::string& shown,
                           int jobs, const std::vector<int>& repetitions,
                           const std::vector<std::string>& scene_names) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Trial> trials = select_trials(b, repetitions, scene_names);
  std::map<int, PreparedScene> scenes;
  // Scene and object names become file names here: a name that is a path would write elsewhere.
  for (const auto& sc : b.scenes)
    for (const auto& t : sc.targets)
      for (const std::string& n : {sc.name, t.object})
        if (n.find_first_of("/\\") != std::string::npos || n.front() == '.')
          throw Error(b.file, "'" + n + "' cannot name a file of the export");
  for (const auto& t : trials) {
    if (b.scenes[t.scene].recorded())
      throw Error(b.file, "scene '" + b.scenes[t.scene].name + "' is recorded already");
    if (!scenes.count(t.scene)) scenes.emplace(t.scene, prepare_scene(b, t.scene));
  }
  fs::create_directories(dir + "/models");
  fs::create_directories(dir + "/refs");
  std::ostringstream yaml;
  yaml << "# Written by `laserfit bench export --bop` from " << b.file
       << ": its simulated scans as\n# recorded scenes. Run: laserfit bench " << shown
       << "/benchmark.yaml\nname: " << b.name << "\nseed: " << b.seed
       << "\ntolerance: {translation_mm: " << io::Json(b.t_tol_mm).dump()
       << ", rotation_deg: " << io::Json(b.r_tol_deg).dump() << "}\nmethods: [";
  for (size_t i = 0; i < b.methods.size(); ++i) yaml << (i ? ", " : "") << name_of(b.methods[i]);
  yaml << "]\nscenes:\n";
  io::Json models = io::Json::object();
  std::map<int, std::map<size_t, int>> obj_ids;  // scene -> target -> obj_id
  for (const auto& [i, p] : scenes) {
    const SceneCase& sc = b.scenes[i];
    yaml << "  - name: " << sc.name << "\n    recorded: " << sc.name << "\n    targets:\n";
    for (size_t k = 0; k < sc.targets.size(); ++k) {
      const int id = int(models.size()) + 1;
      obj_ids[i][k] = id;
      const std::string ref = "refs/" + sc.name + "_" + sc.targets[k].object + ".pcd";
      const std::string model = "models/obj_" + six(id) + ".ply";
      const TriMesh& mesh = p.scene.objects[p.object[k]].mesh;
      io::write_cloud(dir + "/" + ref, p.reference[k]);
      io::write_mesh(dir + "/" + model, mesh, {{"laserfit.object", sc.targets[k].object}});
      models[std::to_string(id)] = model_info(mesh, sc.targets[k].symmetry);
      yaml << target_yaml(sc.targets[k], id, p.object[k], ref, model);
    }
    fs::create_directories(dir + "/" + sc.name + "/scans");
  }
  write_file_atomic(dir + "/models/models_info.json", models.dump(1) + "\n");

  std::map<int, PoseTable> truth, prior;  // per scene
  std::vector<TrialInput> inputs(trials.size());
  parallel_for(trials.size(), jobs, [&](size_t i) {
    const Trial& t = trials[i];
    const TrialInput in = trial_input(b, scenes.at(t.scene), t);
    PointCloud scan = in.scan;
    scan.metadata["benchmark"] = b.name;
    scan.metadata["trial"] = std::to_string(t.index);
    io::write_cloud(dir + "/" + b.scenes[t.scene].name + "/scans/" + six(t.index) + ".pcd", scan);
    inputs[i].truth = in.truth, inputs[i].prior = in.prior;
  });
  for (size_t i = 0; i < trials.size(); ++i)
    for (size_t k = 0; k < inputs[i].truth.size(); ++k) {
      const int s = trials[i].scene, id = obj_ids[s][k];
      truth[s][trials[i].index][id] = inputs[i].truth[k];
      prior[s][trials[i].index][id] = inputs[i].prior[k];
    }
  for (const auto& [s, table] : truth) {
    write_scene_gt(dir + "/" + b.scenes[s].name + "/scene_gt.json", table);
    write_scene_gt(dir + "/" + b.scenes[s].name + "/scene_prior.json", prior.at(s));
  }
  write_file_atomic(dir + "/benchmark.yaml", yaml.str());
  ExportSummary sum;
  sum.trials = trials.size(), sum.objects = models.size();
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

}  // namespace

// Into DIR.partial, renamed when complete: an error leaves no half-written dataset behind.
ExportSummary export_bop(const Benchmark& b, const std::string& dir, int jobs,
                         const std::vector<int>& repetitions,
                         const std::vector<std::string>& scene_names) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
    throw Error(dir, "exists and is not empty; choose another -o or remove it");
  const std::string partial = dir + ".partial";
  fs::remove_all(partial, ec);
  try {
    const ExportSummary s = write_export(b, partial, dir, jobs, repetitions, scene_names);
    fs::remove(dir, ec);  // an empty directory
    fs::rename(partial, dir);
    return s;
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
}

}  // namespace laserfit::bench
