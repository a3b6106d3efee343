// laserfit assemble --profiles P --poses F --hand-eye "x y z qw qx qy qz" -o scan.pcd: a real
// scanner's profiles and its arm's flange poses -> the organized cloud `register` takes.
#include <memory>

#include "command.hpp"
#include "laserfit/core/enum_names.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/profiles.hpp"
#include "laserfit/sensor/assemble.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string profiles, poses, hand_eye, output, layout = "interleaved", scalar = "f64";
  std::string unit = "mm", pose_unit = "mm";
  int width = 0;
  bool zero_is_invalid = false, json = false;
};

int run(const Options& o) {
  io::ProfileFileSettings s;
  s.layout = parse_enum<io::ProfileLayout>(o.layout);
  s.scalar = parse_enum<io::ProfileScalar>(o.scalar);
  s.width = o.width, s.unit = parse_unit(o.unit), s.zero_is_invalid = o.zero_is_invalid;
  const Unit pose_unit = parse_unit(o.pose_unit);
  const io::Profiles profiles = io::read_profiles(o.profiles, s);
  const std::vector<Pose> T_base_flange = io::read_pose_list(o.poses, pose_unit);
  Pose T_flange_sensor = parse_pose(o.hand_eye, "--hand-eye");
  T_flange_sensor.translation() *= unit_to_mm(pose_unit);
  PointCloud c;
  try {
    c = sensor::assemble_scan(profiles, T_base_flange, T_flange_sensor);
  } catch (const Error& e) {
    throw Error(o.profiles + " and " + o.poses, e.what());
  }
  c.metadata["source"] = "laserfit assemble " + o.profiles + " " + o.poses;
  c.metadata["hand_eye"] = pose_to_string(T_flange_sensor);
  io::write_cloud(o.output, c);
  size_t valid = 0;
  for (const auto& p : c.points) valid += p.allFinite();
  emit(o.json,
       io::Json{{"output", o.output},
                {"width", c.width},
                {"height", c.height},
                {"valid_points", valid},
                {"sensor_origin_mm",
                 {c.sensor_origin->x(), c.sensor_origin->y(), c.sensor_origin->z()}}},
       "assembled " + std::to_string(c.height) + " profiles x " + std::to_string(c.width) +
           " points (" + std::to_string(valid) + " measured) -> " + o.output + "\n");
  return 0;
}

}  // namespace

Command add_assemble(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "assemble",
      "A real scanner's profiles + the arm's flange pose per profile + the hand-eye pose -> an "
      "organized scan in the arm's base frame (what register takes), sensor origin in its header.");
  app->add_option("--profiles", o->profiles,
                  "profiles, one per row, x and z per point in the sensor frame: .csv, .bin "
                  "(--width, --scalar) or an organized .pcd/.ply (laserfit scan --raw)")
      ->required();
  app->add_option("--poses", o->poses,
                  "T_base_flange per profile, one row each: x y z qw qx qy qz, or a row-major 4x4")
      ->required();
  app->add_option("--hand-eye", o->hand_eye,
                  "T_flange_sensor: the scanner in the flange frame, 'x y z qw qx qy qz'")
      ->required();
  app->add_option("-o,--output", o->output, "organized cloud (.pcd/.ply), mm")->required();
  app->add_option("--layout", o->layout,
                  "x and z in a row: interleaved (x0 z0 x1 z1 ...) | blocks (all x, then all z)")
      ->check(CLI::IsMember(names_of<io::ProfileLayout>()))
      ->capture_default_str();
  app->add_option("--scalar", o->scalar, ".bin number type, little endian: f32 | f64")
      ->check(CLI::IsMember(names_of<io::ProfileScalar>()))
      ->capture_default_str();
  app->add_option("--width", o->width, "points per profile (.bin: required; .csv: checked)")
      ->check(CLI::Range(0, 100000));
  tools::add_unit_option(*app, "--unit", o->unit, "unit of the profiles' x and z");
  tools::add_unit_option(*app, "--pose-unit", o->pose_unit,
                         "unit of the translations of --poses and --hand-eye (a ROS arm: m)");
  app->add_flag("--zero-is-invalid", o->zero_is_invalid,
                "z = 0 marks no measurement (else only NaN or an empty field does)");
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
