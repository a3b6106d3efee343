// Writing generated models: meshes + the parameters that made them (cad/ in the repository).
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <sstream>

#include "laserfit/cad/generator.hpp"
#include "laserfit/cad/repair.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/io/mesh_writer.hpp"

namespace laserfit::cad {
namespace {

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The parameters that made a model, next to its meshes: regenerate with `make cad`.
std::string params_yaml(const cad::GeneratedModel& g,
                        const std::vector<cad::RepairReport>& checks) {
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
    y << YAML::Key << "bbox_mm" << YAML::Value << YAML::Flow
      << std::vector<float>{e.x(), e.y(), e.z()};
    y << YAML::Key << "watertight" << YAML::Value << checks[i].watertight;
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  return std::string(y.c_str()) + "\n";
}

}  // namespace

std::vector<std::string> write_model(const GeneratedModel& g, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> files;
  std::vector<RepairReport> checks;
  for (const auto& p : g.parts) {
    TriMesh copy = p.mesh;
    checks.push_back(check_and_repair(copy, {false, false, true}, p.name));
    std::map<std::string, std::string> comments{
        {"source", "laserfit cad " + g.model}, {"unit", "mm"}, {"frame", p.frame}};
    for (const auto& [k, v] : g.params) comments["param." + k] = number(v);
    files.push_back((std::filesystem::path(dir) / (p.name + ".ply")).string());
    io::write_mesh(files.back(), p.mesh, comments);
  }
  files.push_back((std::filesystem::path(dir) / (g.model + ".yaml")).string());
  write_file_atomic(files.back(), params_yaml(g, checks));
  return files;
}

}  // namespace laserfit::cad
