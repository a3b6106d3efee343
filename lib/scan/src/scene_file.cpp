// Scene files (YAML). Strict: an unknown key is an error (a typo must not silently fall back to a
// default), and every problem is reported as "<scene file>: <where>: <what>".
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/io/yaml_reader.hpp"
#include "laserfit/scan/scanner.hpp"

namespace laserfit::scan {
namespace {

using Reader = io::YamlReader;

void read_sensor(const Reader& R, const YAML::Node& n, sensor::LineScannerGeometry& g) {
  double ppp = g.points_per_profile;
  R.numbers(n, "sensor",
            {{"points_per_profile", &ppp},
             {"z_min_mm", &g.z_min_mm},
             {"z_max_mm", &g.z_max_mm},
             {"width_mid_mm", &g.width_mid_mm},
             {"triangulation_angle_deg", &g.triangulation_angle_deg},
             {"max_incidence_deg", &g.max_incidence_deg},
             {"max_camera_angle_deg", &g.max_camera_angle_deg}});
  if (ppp != std::floor(ppp) || ppp < 2 || ppp > 65536)
    R.fail("sensor.points_per_profile", "must be an integer in 2..65536");
  g.points_per_profile = static_cast<int>(ppp);
}

void read_sweep(const Reader& R, const YAML::Node& n, SweepSettings& s) {
  R.only(n, "sweep",
         {"start", "center", "direction", "length_mm", "speed_mm_s", "profile_rate_hz"});
  if (!!n["start"] == !!n["center"])
    R.fail("sweep",
           "give either 'start' (sensor pose at the first profile) or 'center' (at mid-sweep)");
  const YAML::Node p = n["start"] ? n["start"] : n["center"];
  const std::string where = n["start"] ? "sweep.start" : "sweep.center";
  if (p.IsMap()) {  // {look_from: [x,y,z], look_at: [x,y,z], line: [x,y,z]} instead of a pose
    R.only(p, where, {"look_from", "look_at", "line"});
    if (!p["look_from"] || !p["look_at"]) R.fail(where, "needs look_from and look_at");
    auto vec = [&](const char* k) {
      const auto v = R.list(p[k], where + "." + k);
      if (v.size() != 3) R.fail(where + "." + k, "expected [x, y, z]");
      return Eigen::Vector3d(v[0], v[1], v[2]);
    };
    const Eigen::Vector3d from = vec("look_from"), at = vec("look_at");
    if ((at - from).norm() < 1e-9) R.fail(where, "look_from and look_at coincide");
    s.T_base_sensor_start = look_at(from, at, p["line"] ? vec("line") : Eigen::Vector3d::UnitX());
  } else {
    s.T_base_sensor_start = R.pose(p, where);
  }
  if (n["direction"]) {
    const auto d = R.list(n["direction"], "sweep.direction");
    if (d.size() != 3 || Eigen::Vector3d(d[0], d[1], d[2]).norm() < 1e-9)
      R.fail("sweep.direction", "expected a non-zero [x, y, z] in the sensor frame");
    s.direction = Eigen::Vector3d(d[0], d[1], d[2]).normalized();
  }
  s.length_mm = R.num(n, "length_mm", s.length_mm, "sweep");
  s.speed_mm_s = R.num(n, "speed_mm_s", s.speed_mm_s, "sweep");
  s.profile_rate_hz = R.num(n, "profile_rate_hz", s.profile_rate_hz, "sweep");
  if (n["center"]) {  // the given pose is mid-sweep: step back half the sweep along its direction
    Pose back = Pose::Identity();
    back.translation() = -0.5 * s.length_mm * s.direction;
    s.T_base_sensor_start = s.T_base_sensor_start * back;
  }
}

void read_noise(const Reader& R, const YAML::Node& n, NoiseSettings& s) {
  R.numbers(n, "noise",
            {{"depth_sigma_um", &s.depth_sigma_um},
             {"x_jitter_um", &s.x_jitter_um},
             {"z_quantum_um", &s.z_quantum_um},
             {"speckle_sigma_um", &s.speckle_sigma_um},
             {"speckle_corr_um", &s.speckle_corr_um},
             {"dropout_rate", &s.dropout_rate},
             {"grazing_start_deg", &s.grazing_start_deg},
             {"mixed_pixel_prob", &s.mixed_pixel_prob},
             {"mixed_pixel_jump_mm", &s.mixed_pixel_jump_mm},
             {"outlier_rate", &s.outlier_rate},
             {"outlier_max_mm", &s.outlier_max_mm},
             {"bias_sigma_um", &s.bias_sigma_um}},
            {"enabled"});
  s.enabled = R.flag(n, "enabled", s.enabled, "noise");
}

void read_motion(const Reader& R, const YAML::Node& n, MotionSettings& s) {
  R.numbers(n, "motion",
            {{"offset_sigma_mm", &s.offset_sigma_mm},
             {"offset_sigma_deg", &s.offset_sigma_deg},
             {"jitter_sigma_mm", &s.jitter_sigma_mm},
             {"jitter_sigma_deg", &s.jitter_sigma_deg},
             {"jitter_corr_profiles", &s.jitter_corr_profiles}},
            {"enabled", "calibration_error"});
  s.enabled = R.flag(n, "enabled", s.enabled, "motion");
  if (n["calibration_error"]) {
    const auto c = R.list(n["calibration_error"], "motion.calibration_error");
    if (c.size() != 6)
      R.fail("motion.calibration_error", "expected [x, y, z (mm), rx, ry, rz (deg)]");
    std::copy(c.begin(), c.end(), s.calibration_error.begin());
  }
}

}  // namespace

static ScanScene load_scene_unguarded(const std::string& path) {
  namespace fs = std::filesystem;
  require_input_file(path);
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw Error(path, std::string("not valid YAML: ") + e.what());
  }
  const Reader R{path};
  if (!root || root.IsNull()) R.fail("scene", "file is empty");
  R.only(root, "scene", {"seed", "objects", "sensor", "sweep", "noise", "motion"});
  ScanScene sc;
  sc.file = path;
  sc.seed = R.seed(root, "seed", sc.seed, "scene");
  if (root["sensor"]) read_sensor(R, root["sensor"], sc.settings.sensor);
  if (!root["sweep"]) R.fail("scene", "missing 'sweep'");
  read_sweep(R, root["sweep"], sc.settings.sweep);
  if (root["noise"]) read_noise(R, root["noise"], sc.settings.noise);
  if (root["motion"]) read_motion(R, root["motion"], sc.settings.motion);

  const YAML::Node objs = root["objects"];
  if (!objs || !objs.IsSequence() || objs.size() == 0) R.fail("objects", "need a non-empty list");
  std::map<std::string, TriMesh> cache;
  for (size_t i = 0; i < objs.size(); ++i) {
    const std::string where = "objects[" + std::to_string(i) + "]";
    R.only(objs[i], where, {"name", "mesh", "pose", "shiny"});
    SceneObject o;
    o.name = objs[i]["name"] ? objs[i]["name"].as<std::string>() : "object" + std::to_string(i);
    if (!objs[i]["mesh"]) R.fail(where, "missing 'mesh'");
    o.mesh_path = objs[i]["mesh"].as<std::string>();
    if (!objs[i]["pose"]) R.fail(where, "missing 'pose' (T_base_object)");
    o.T_base_object = R.pose(objs[i]["pose"], where + ".pose");
    o.shiny = R.flag(objs[i], "shiny", false, where);
    const fs::path mesh = fs::path(path).parent_path() / o.mesh_path;
    std::error_code ec;  // set when the OS refuses the path (too long, a loop of links)
    if (!fs::exists(mesh, ec))
      R.fail(where + ".mesh",
             std::string(ec ? "cannot use the mesh path '" : "no such mesh file '") +
                 shown_path(mesh.string()) + "'" + (ec ? ": " + ec.message() : ""));
    auto it = cache.find(mesh.string());
    if (it == cache.end())
      it = cache.emplace(mesh.string(), cad::import_cad(mesh.string()).mesh).first;
    o.mesh = it->second;
    sc.objects.push_back(std::move(o));
  }
  sc.settings.validate(path);
  return sc;
}

ScanScene load_scene(const std::string& path) {
  return io::guard_yaml(path, [&] { return load_scene_unguarded(path); });
}

}  // namespace laserfit::scan
