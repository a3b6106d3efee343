// Cell files (YAML, mm / deg). Strict: unknown keys are errors naming the file and the key.
#include <filesystem>

#include "laserfit/cell/cell.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/yaml_reader.hpp"
#include "laserfit/scan/reference.hpp"

namespace laserfit::cell {
namespace {

using io::YamlReader;

RigidError rigid(const YamlReader& R, const YAML::Node& n, const std::string& key,
                 const std::string& where) {
  RigidError e{};
  if (!n[key]) return e;
  const auto v = R.list(n[key], where + "." + key);
  if (v.size() != 6) R.fail(where + "." + key, "expected [x, y, z (mm), rx, ry, rz (deg)]");
  for (int i = 0; i < 6; ++i) e[i] = v[i];
  if (Eigen::Vector3d(e[0], e[1], e[2]).norm() > 50 ||
      Eigen::Vector3d(e[3], e[4], e[5]).norm() > 30)
    R.fail(where + "." + key, "an error above 50 mm or 30 deg is not a calibration error");
  return e;
}

robot::Joints joints(const YamlReader& R, const YAML::Node& n, const std::string& where) {
  const auto v = R.list(n, where);
  if (v.size() != 7) R.fail(where, "expected 7 joint angles (deg)");
  robot::Joints q;
  for (int i = 0; i < 7; ++i) q[i] = v[i] * M_PI / 180;
  return q;
}

std::string axis_name(const YamlReader& R, const YAML::Node& n, const std::string& key,
                      const std::string& where) {
  const std::string a = R.str(n, key, "", where);
  if (!a.empty() && a != "x" && a != "y" && a != "z")
    R.fail(where + "." + key, "must be x, y or z");
  return a;
}

}  // namespace

static CellSettings load_cell_unguarded(const std::string& path) {
  const YamlReader R{path};
  const YAML::Node root = R.load();
  R.only(root, "cell",
         {"task", "scene", "target", "part", "target_poses", "insertion", "clearance",
          "assembling_arm", "sensing_arm", "arm_errors", "start_configs", "start_step_mm",
          "ic2_joint1_deg", "weak"});
  CellSettings c;
  c.file = path;
  c.task = R.str(root, "task", "", "cell");
  const auto dir = std::filesystem::path(path).parent_path();
  R.need(root, "scene", "cell");
  c.scene = scan::load_scene((dir / R.str(root, "scene", "", "cell")).lexically_normal().string());
  auto object = [&](const std::string& key) {
    R.need(root, key, "cell");
    const std::string name = R.str(root, key, "", "cell");
    for (size_t i = 0; i < c.scene.objects.size(); ++i)
      if (c.scene.objects[i].name == name) return int(i);
    R.fail(key, "the scene has no object '" + name + "'");
  };
  c.target = object("target"), c.part = object("part");
  const auto tp = R.need(root, "target_poses", "cell");
  if (!tp.IsSequence() || tp.size() == 0)
    R.fail("target_poses", "expected a list of poses [x, y, z, qw, qx, qy, qz]");
  for (size_t i = 0; i < tp.size(); ++i)
    c.target_poses.push_back(R.pose(tp[i], "target_poses[" + std::to_string(i) + "]"));

  const auto ins = R.need(root, "insertion", "cell");
  R.only(ins, "insertion",
         {"part_in_target", "approach_mm", "stages", "push_mm", "clear_view_mm",
          "max_correction_mm", "max_correction_deg"});
  c.T_target_part_insert =
      R.pose(R.need(ins, "part_in_target", "insertion"), "insertion.part_in_target");
  const auto ap = R.list(R.need(ins, "approach_mm", "insertion"), "insertion.approach_mm");
  if (ap.size() != 3 || Eigen::Vector3d(ap[0], ap[1], ap[2]).norm() > 50)
    R.fail("insertion.approach_mm", "expected [x, y, z] within 50 mm of the insertion pose");
  c.approach_mm = {ap[0], ap[1], ap[2]};
  if (ins["stages"]) {
    c.stages = R.list(ins["stages"], "insertion.stages");
    for (size_t i = 0; i < c.stages.size(); ++i)
      if (!(c.stages[i] > (i ? c.stages[i - 1] : 0.0) && c.stages[i] < 1))
        R.fail("insertion.stages", "fractions must increase strictly within (0, 1)");
  }
  c.push_mm = R.num(ins, "push_mm", c.push_mm, "insertion");
  if (!(c.push_mm >= 0 && c.push_mm <= 20))
    R.fail("insertion.push_mm", "the push past the insertion pose must be in [0, 20] mm");
  if (ins["clear_view_mm"]) {
    const auto cv = R.list(ins["clear_view_mm"], "insertion.clear_view_mm");
    if (cv.size() != 3 || !(Eigen::Vector3d(cv[0], cv[1], cv[2]).norm() <= 30))
      R.fail("insertion.clear_view_mm", "expected [x, y, z], a step of at most 30 mm");
    c.clear_view_mm = {cv[0], cv[1], cv[2]};
  }
  c.max_correction_mm = R.num(ins, "max_correction_mm", c.max_correction_mm, "insertion");
  c.max_correction_deg = R.num(ins, "max_correction_deg", c.max_correction_deg, "insertion");
  if (!(c.max_correction_mm > 0 && c.max_correction_mm <= 50))
    R.fail("insertion.max_correction_mm", "the correction limit must be in (0, 50] mm");
  if (!(c.max_correction_deg > 0 && c.max_correction_deg <= 30))
    R.fail("insertion.max_correction_deg", "the correction limit must be in (0, 30] deg");

  const auto cl = R.need(root, "clearance", "cell");
  R.numbers(cl, "clearance",
            {{"x_mm", &c.clearance.x_mm},
             {"y_mm", &c.clearance.y_mm},
             {"angle_deg", &c.clearance.angle_deg},
             {"depth_mm", &c.clearance.depth_mm}});
  if (!(c.clearance.x_mm > 0 && c.clearance.y_mm > 0 && c.clearance.angle_deg > 0 &&
        c.clearance.x_mm < 10 && c.clearance.y_mm < 10 && c.clearance.depth_mm >= 0 &&
        c.clearance.depth_mm < 10))
    R.fail("clearance",
           "half-widths must be in (0, 10) mm, the angle positive, depth_mm in [0, 10) mm");

  const auto a = R.need(root, "assembling_arm", "cell");
  R.only(a, "assembling_arm", {"base", "base_error", "grasp", "grasp_error", "teach_near_deg"});
  c.T_world_baseA = R.pose(R.need(a, "base", "assembling_arm"), "assembling_arm.base");
  c.baseA_error = rigid(R, a, "base_error", "assembling_arm");
  c.T_flange_part = R.pose(R.need(a, "grasp", "assembling_arm"), "assembling_arm.grasp");
  c.grasp_error = rigid(R, a, "grasp_error", "assembling_arm");
  c.q_teach_hint =
      joints(R, R.need(a, "teach_near_deg", "assembling_arm"), "assembling_arm.teach_near_deg");

  const auto sa = R.need(root, "sensing_arm", "cell");
  R.only(sa, "sensing_arm",
         {"sensor", "sensor_error", "scan_near_deg", "approach_sweep_mm", "search_sweep_mm",
          "search_raise_mm"});
  c.T_flange_sensor = R.pose(R.need(sa, "sensor", "sensing_arm"), "sensing_arm.sensor");
  c.sensor_error = rigid(R, sa, "sensor_error", "sensing_arm");
  c.q_sense_hint =
      joints(R, R.need(sa, "scan_near_deg", "sensing_arm"), "sensing_arm.scan_near_deg");
  c.search_sweep_mm = R.num(sa, "search_sweep_mm", 0, "sensing_arm");
  if (!(c.search_sweep_mm == 0 ||
        (c.search_sweep_mm >= c.scene.settings.sweep.length_mm && c.search_sweep_mm <= 100)))
    R.fail("sensing_arm.search_sweep_mm",
           "must be 0 (none) or from the scene's sweep length up to 100 mm");
  c.approach_sweep_mm = R.num(sa, "approach_sweep_mm", 0, "sensing_arm");
  if (!(c.approach_sweep_mm == 0 ||
        (c.approach_sweep_mm >= c.scene.settings.sweep.length_mm && c.approach_sweep_mm <= 100)))
    R.fail("sensing_arm.approach_sweep_mm",
           "must be 0 (the scene's sweep) or from the scene's sweep length up to 100 mm");
  // The raised scan must still see the target: its range from the sweep's middle plus the raise
  // stays inside the far limit.
  const auto& sc = c.scene.settings;
  const double far_mm =
      sc.sensor.z_max_mm -
      (scan::mid_sweep(sc).inverse() * c.scene.objects[c.target].T_base_object).translation().z();
  c.search_raise_mm = R.num(sa, "search_raise_mm", 0, "sensing_arm");
  if (!(c.search_raise_mm >= 0 && c.search_raise_mm < far_mm))
    R.fail("sensing_arm.search_raise_mm",
           "must be 0 (none) or less than the target's distance to the scanner's far limit (" +
               std::to_string(far_mm) + " mm)");

  if (const auto e = root["arm_errors"]) {
    auto& m = c.arm_errors;
    R.numbers(e, "arm_errors",
              {{"length_min_mm", &m.length_min_mm},
               {"length_max_mm", &m.length_max_mm},
               {"angle_min_mrad", &m.angle_min_mrad},
               {"angle_max_mrad", &m.angle_max_mrad},
               {"repeatability_mm", &m.repeatability_mm},
               {"repeatability_mrad", &m.repeatability_mrad},
               {"repeatability_corr_mm", &m.repeatability_corr_mm}});
    try {
      m.validate();
    } catch (const Error& err) {
      R.fail("arm_errors", err.what());
    }
  }
  c.start_configs = int(R.integer(root, "start_configs", 10, "cell", 1, 1000));
  c.start_step_mm = R.num(root, "start_step_mm", 25, "cell");
  if (!(c.start_step_mm >= 0 && c.start_step_mm <= 100))
    R.fail("start_step_mm", "must be in 0..100 mm");
  c.ic2_joint1_deg = R.num(root, "ic2_joint1_deg", 90, "cell");
  if (std::abs(c.ic2_joint1_deg) > 180) R.fail("ic2_joint1_deg", "must be within +-180 deg");
  if (const auto w = root["weak"]) {
    R.only(w, "weak",
           {"target_rotation", "target_translation", "part_rotation", "part_translation"});
    c.target_weak_rotation = axis_name(R, w, "target_rotation", "weak");
    c.target_weak_translation = axis_name(R, w, "target_translation", "weak");
    c.part_weak_rotation = axis_name(R, w, "part_rotation", "weak");
    c.part_weak_translation = axis_name(R, w, "part_translation", "weak");
  }
  return c;
}

CellSettings load_cell(const std::string& path) {
  return io::guard_yaml(path, [&] { return load_cell_unguarded(path); });
}

}  // namespace laserfit::cell
