// laserfit refcloud <mesh> -o <cloud.pcd|ply>: full or view-dependent reference cloud.
#include <chrono>
#include <memory>
#include <sstream>

#include "command.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/sampling/sampling.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string input, output, unit = "auto", method = "uniform";
  long long count = 0;
  double density = 0.0, max_incidence = 80.0, oversampling = 5.0, timeout = 60.0, memory = 8192.0;
  uint64_t seed = 1;
  std::vector<std::string> views, view_dirs;
  bool static_sensor = false, json = false;
  int jobs = 0;
};

// Sensor on the ray from the part's bbox centre along `dir`, looking back at the centre, placed so
// that the part's nearest bbox face lies 10 % into the measuring range (as an operator would
// place a part: the front in range, as much depth as the range allows behind it).
Pose view_from_direction(const std::string& text, const TriMesh& mesh,
                         const sensor::LineScannerGeometry& g) {
  std::istringstream in([&] {
    std::string s = text;
    for (char& c : s)
      if (c == ',') c = ' ';
    return s;
  }());
  Eigen::Vector3d d;
  if (!(in >> d.x() >> d.y() >> d.z()) || !d.allFinite() || d.norm() < 1e-9)
    throw Error("--view-dir '" + text + "': expected a non-zero direction 'x y z'");
  const Eigen::AlignedBox3d box = mesh.bbox().cast<double>();
  const Eigen::Vector3d centre = box.center(), u = d.normalized();
  const double support =
      0.5 * box.sizes().cwiseProduct(u.cwiseAbs()).sum();  // bbox half-depth along u
  const Eigen::Vector3d eye = centre + u * (support + g.z_min_mm + 0.1 * (g.z_max_mm - g.z_min_mm));
  // Keep the laser line (sensor x) horizontal-ish: hint x unless we look along x.
  const Eigen::Vector3d hint =
      std::abs(d.normalized().x()) > 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  return look_at(eye, centre, hint);
}

int run(const Options& o) {
  const auto t0 = std::chrono::steady_clock::now();
  cad::ImportSettings is;
  is.unit = parse_unit(o.unit);
  is.reader.timeout_s = o.timeout;
  is.reader.memory_mib = o.memory;
  const auto imported = cad::import_cad(o.input, is);
  const TriMesh& mesh = imported.mesh;

  sampling::SamplingSettings s;
  s.count = static_cast<size_t>(o.count);
  s.density_per_mm2 = o.density;
  s.seed = o.seed;
  s.poisson_oversampling = o.oversampling;
  if (o.method == "uniform")
    s.method = sampling::Method::Uniform;
  else if (o.method == "poisson")
    s.method = sampling::Method::PoissonDisk;
  else
    throw Error("--method must be 'uniform' or 'poisson', not '" + o.method + "'");

  sampling::ViewSettings v;
  v.geometry.max_incidence_deg = o.max_incidence;
  v.swept = !o.static_sensor;
  for (const auto& t : o.views) v.T_mesh_sensor.push_back(parse_pose(t, "--view"));
  for (const auto& t : o.view_dirs)
    v.T_mesh_sensor.push_back(view_from_direction(t, mesh, v.geometry));

  PointCloud cloud;
  try {
    cloud = v.T_mesh_sensor.empty()
                ? (s.method == sampling::Method::Uniform ? sampling::sample_uniform(mesh, s)
                                                         : sampling::sample_poisson_disk(mesh, s))
                : sampling::sample_visible(mesh, v, s);
  } catch (const Error& e) {
    throw Error(o.input, e.what());
  }
  cloud.metadata["source"] = o.input;
  cloud.metadata["unit"] = "mm";
  cloud.metadata["source_unit"] = unit_name(imported.unit) + " (" + imported.unit_source + ")";
  cloud.metadata["normals"] = "outward face normals";
  cloud.metadata["views"] = std::to_string(v.T_mesh_sensor.size());
  for (size_t i = 0; i < v.T_mesh_sensor.size(); ++i)
    cloud.metadata["view" + std::to_string(i) + ".T_mesh_sensor"] =
        pose_to_string(v.T_mesh_sensor[i]);
  if (!v.T_mesh_sensor.empty())
    cloud.metadata["sensor"] = std::string(v.swept ? "swept line scanner" : "static") +
                               ", max incidence " + std::to_string(o.max_incidence) + " deg";
  io::write_cloud(o.output, cloud);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  io::Json views = io::Json::array();
  for (const auto& T : v.T_mesh_sensor) views.push_back(io::pose_to_json(T));
  io::Json j{{"input", o.input},       {"output", o.output},
             {"points", cloud.size()}, {"method", cloud.metadata["method"]},
             {"seed", o.seed},         {"mesh_area_mm2", mesh.area()},
             {"views", views},         {"seconds", secs}};
  if (cloud.metadata.count("visible_area_mm2"))
    j["visible_area_mm2"] = std::stod(cloud.metadata["visible_area_mm2"]);
  std::ostringstream h;
  h << "wrote " << o.output << ": " << cloud.size() << " points (" << cloud.metadata["method"]
    << ", seed " << o.seed << ") from " << o.input;
  if (!v.T_mesh_sensor.empty())
    h << ", visible from " << v.T_mesh_sensor.size()
      << " view(s): " << cloud.metadata["visible_area_mm2"] << " of " << mesh.area() << " mm^2";
  h << "\n";
  emit(o.json, j, h.str());
  return 0;
}

}  // namespace

Command add_refcloud(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "refcloud",
      "Sample a reference cloud from a mesh: the full surface, or only what a line scanner sees "
      "from given viewpoints (Embree visibility: laser and camera shadows, incidence cut-off).");
  app->add_option("mesh", o->input, "mesh or CAD file (any format `laserfit import` reads)")
      ->required();
  app->add_option("-o,--output", o->output, "output cloud (.pcd binary or .ply), mm, with normals")
      ->required();
  auto* count = app->add_option("-n,--count", o->count, "number of points (1 to 100 000 000)")
                    ->check(CLI::Range(1LL, 100'000'000LL));
  auto* density =
      app->add_option("--density", o->density, "points per mm^2 of (visible) surface (> 0)")
          ->check(CLI::PositiveNumber);
  count->excludes(density);
  app->add_option("--method", o->method, "uniform | poisson (Poisson-disk, sample elimination)")
      ->capture_default_str();
  app->add_option("--seed", o->seed, "random seed (written into the output)")
      ->capture_default_str();
  app->add_option("--view", o->views,
                  "viewpoint: sensor pose in the mesh frame, T_mesh_sensor, as 'x y z qw qx qy qz' "
                  "(mm) or 16 numbers; sensor z = viewing direction, y = sweep. Repeatable: views "
                  "are merged");
  app->add_option(
      "--view-dir", o->view_dirs,
      "viewpoint from a direction 'x y z' (mesh frame): the sensor looks back along it "
      "at the bbox centre, the part's near face 10% into the measuring range. Repeatable");
  app->add_option("--max-incidence", o->max_incidence, "incidence cut-off for views (deg)")
      ->check(CLI::Range(0.0, 90.0))
      ->capture_default_str();
  app->add_flag("--static", o->static_sensor,
                "views are static (emitter at the sensor origin), not swept");
  app->add_option("--oversampling", o->oversampling, "Poisson-disk candidates per point")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  add_reader_limits(*app, o->timeout, o->memory);
  app->add_option("--unit", o->unit, "unit of the mesh file (as for import)")
      ->capture_default_str();
  add_jobs(*app, o->jobs);
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  return {app, [o] {
            if (o->count == 0 && o->density <= 0) throw Error("give --count N or --density D");
            return run(*o);
          }};
}

}  // namespace laserfit::cli
