// laserfit cad <model|all> -o DIR: the project's parametric CAD (needle, thread, Task Board 1).
#include <filesystem>
#include <memory>
#include <sstream>

#include "command.hpp"
#include "laserfit/cad/generator.hpp"
#include "laserfit/core/error.hpp"

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
    if (eq == std::string::npos || eq == 0 || end == s.c_str() + eq + 1 || *end != '\0' ||
        !std::isfinite(v))
      throw Error("--set '" + s + "': expected name=value (mm)");
    out[s.substr(0, eq)] = v;
  }
  return out;
}

int run(const Options& o) {
  if (o.list) {
    io::Json j = io::Json::array();
    std::ostringstream h;
    for (const auto& m : cad::model_catalogue()) {
      io::Json params = io::Json::array();
      h << m.name << " — " << m.description << "\n";
      for (const auto& p : m.params) {
        params.push_back({{"name", p.name},
                          {"default", p.value},
                          {"min", p.min},
                          {"max", p.max},
                          {"unit", p.unit},
                          {"help", p.help}});
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
    const auto files = cad::write_model(g, o.outdir);
    io::Json parts = io::Json::array();
    for (size_t i = 0; i < g.parts.size(); ++i) {
      const auto& p = g.parts[i];
      const Eigen::Vector3f e = p.mesh.extent();
      parts.push_back({{"file", files[i]},
                       {"triangles", p.mesh.faces.size()},
                       {"bbox_mm", {e.x(), e.y(), e.z()}}});
      h << "wrote " << files[i] << ": " << p.mesh.faces.size() << " triangles, " << e.x() << " x "
        << e.y() << " x " << e.z() << " mm\n";
    }
    const std::string yaml = files.back();
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
      "cad",
      "Generate the project's parametric CAD models (needle + thread tip, NIST Task Board 1 "
      "USB-A plug/receptacle, round and square pegs with holes) as mm meshes + parameters.");
  app->add_option("model", o->model, "model name, or 'all'");
  app->add_option("-o,--output,--outdir", o->outdir, "output directory")->capture_default_str();
  app->add_option("--set", o->sets, "override a parameter: name=value (mm); repeatable");
  app->add_flag("--list", o->list, "list models and their parameters");
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
