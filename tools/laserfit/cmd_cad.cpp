// laserfit cad <model|all> -o DIR: the project's parametric CAD (needle, thread, Task Board 1).
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <memory>
#include <sstream>

#include "command.hpp"
#include "laserfit/cad/generator.hpp"
#include "laserfit/cad/repair.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/mesh_writer.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string model, outdir = "cad";
  std::vector<std::string> sets;
  bool list = false, json = false;
};

std::map<std::string, double> parse_sets(const std::vector<std::string>& sets) {
  std::map<std::string, double> out;
  for (const auto& s : sets) {
    const auto eq = s.find('=');
    char* end = nullptr;
    const double v = eq == std::string::npos ? 0.0 : std::strtod(s.c_str() + eq + 1, &end);
    if (eq == std::string::npos || eq == 0 || end == s.c_str() + eq + 1 || *end != '\0' || !std::isfinite(v))
      throw Error("--set '" + s + "': expected name=value (mm)");
    out[s.substr(0, eq)] = v;
  }
  return out;
}

// The parameters that made a model, next to its meshes: regenerate with `make cad`.
std::string params_yaml(const cad::GeneratedModel& g, const std::vector<cad::RepairReport>& checks) {
  YAML::Emitter y;
  y << YAML::BeginMap << YAML::Key << "model" << YAML::Value << g.model;
  y << YAML::Key << "generator" << YAML::Value << "laserfit cad (OpenCASCADE B-rep, BRepMesh)";
  y << YAML::Key << "unit" << YAML::Value << "mm";
  y << YAML::Key << "deflection_mm" << YAML::Value << g.deflection_mm;
  y << YAML::Key << "params" << YAML::Value << YAML::BeginMap;
  for (const auto& [k, v] : g.params) y << YAML::Key << k << YAML::Value << v;
  y << YAML::EndMap << YAML::Key << "parts" << YAML::Value << YAML::BeginSeq;
  for (size_t i = 0; i < g.parts.size(); ++i) {
    const auto& p = g.parts[i];
    const Eigen::Vector3f e = p.mesh.extent();
    y << YAML::BeginMap << YAML::Key << "file" << YAML::Value << p.name + ".ply";
    y << YAML::Key << "frame" << YAML::Value << p.frame;
    y << YAML::Key << "triangles" << YAML::Value << p.mesh.faces.size();
    y << YAML::Key << "bbox_mm" << YAML::Value << YAML::Flow << std::vector<float>{e.x(), e.y(), e.z()};
    y << YAML::Key << "watertight" << YAML::Value << checks[i].watertight;
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  return std::string(y.c_str()) + "\n";
}

int run(const Options& o) {
  if (o.list) {
    io::Json j = io::Json::array();
    std::ostringstream h;
    for (const auto& m : cad::model_catalogue()) {
      io::Json params = io::Json::array();
      h << m.name << " — " << m.description << "\n";
      for (const auto& p : m.params) {
        params.push_back({{"name", p.name}, {"default", p.value}, {"min", p.min}, {"max", p.max},
                          {"unit", p.unit}, {"help", p.help}});
        h << "  " << p.name << " = " << p.value << " " << p.unit << "  [" << p.min << ", " << p.max
          << "]  " << p.help << "\n";
      }
      j.push_back({{"model", m.name}, {"description", m.description}, {"params", params}});
    }
    emit(o.json, j, h.str());
    return 0;
  }
  if (o.model.empty()) throw Error("name a model (or 'all'); see --list");
  std::vector<std::string> models;
  if (o.model == "all") {
    if (!o.sets.empty()) throw Error("--set applies to one model, not 'all'");
    for (const auto& m : cad::model_catalogue()) models.push_back(m.name);
  } else {
    models.push_back(o.model);
  }
  const auto overrides = parse_sets(o.sets);
  std::filesystem::create_directories(o.outdir);
  io::Json j = io::Json::array();
  std::ostringstream h;
  for (const auto& name : models) {
    const cad::GeneratedModel g = cad::generate_model(name, overrides);
    std::vector<cad::RepairReport> checks;
    for (const auto& p : g.parts) {
      TriMesh copy = p.mesh;
      checks.push_back(cad::check_and_repair(copy, {false, false, true}, p.name));
    }
    io::Json parts = io::Json::array();
    for (size_t i = 0; i < g.parts.size(); ++i) {
      const auto& p = g.parts[i];
      const std::string file = (std::filesystem::path(o.outdir) / (p.name + ".ply")).string();
      std::map<std::string, std::string> comments{{"source", "laserfit cad " + name}, {"unit", "mm"},
                                                  {"frame", p.frame}};
      for (const auto& [k, v] : g.params) {
        std::ostringstream s;
        s << v;
        comments["param." + k] = s.str();
      }
      io::write_mesh(file, p.mesh, comments);
      const Eigen::Vector3f e = p.mesh.extent();
      parts.push_back({{"file", file}, {"triangles", p.mesh.faces.size()},
                       {"bbox_mm", {e.x(), e.y(), e.z()}}, {"watertight", checks[i].watertight}});
      h << "wrote " << file << ": " << p.mesh.faces.size() << " triangles, " << e.x() << " x "
        << e.y() << " x " << e.z() << " mm, " << (checks[i].watertight ? "watertight" : "NOT watertight")
        << "\n";
    }
    const std::string yaml = (std::filesystem::path(o.outdir) / (name + ".yaml")).string();
    write_file_atomic(yaml, params_yaml(g, checks));
    h << "wrote " << yaml << "\n";
    j.push_back({{"model", name}, {"params", g.params}, {"parts", parts}, {"params_file", yaml}});
  }
  emit(o.json, j, h.str());
  return 0;
}

}  // namespace

Command add_cad(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "cad", "Generate the project's parametric CAD models (needle + thread tip, NIST Task Board 1 "
             "USB-A plug/receptacle, round and square pegs with holes) as mm meshes + parameters.");
  app->add_option("model", o->model, "model name, or 'all'");
  app->add_option("-o,--outdir", o->outdir, "output directory")->capture_default_str();
  app->add_option("--set", o->sets, "override a parameter: name=value (mm); repeatable");
  app->add_flag("--list", o->list, "list models and their parameters");
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
