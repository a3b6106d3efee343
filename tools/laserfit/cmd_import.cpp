// laserfit import <file> -o <mesh.ply|stl>: any CAD/mesh file -> checked, repaired mm mesh.
#include <memory>
#include <sstream>

#include "command.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/io/mesh_writer.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string input, output, unit = "auto", part;
  double deflection = 0.01, angular = 0.2, timeout = 60.0, memory = 8192.0;
  bool no_repair = false, fill_holes = false, no_self_check = false, json = false;
};

io::Json repair_json(const cad::RepairReport& r) {
  return {{"duplicate_vertices_merged", r.duplicate_vertices_merged},
          {"degenerate_faces_removed", r.degenerate_faces_removed},
          {"duplicate_faces_removed", r.duplicate_faces_removed},
          {"non_manifold_edges", r.non_manifold_edges},
          {"non_manifold_vertices_split", r.non_manifold_vertices_split},
          {"faces_reoriented", r.faces_reoriented},
          {"holes", r.holes},
          {"holes_filled", r.holes_filled},
          {"boundary_edges", r.boundary_edges},
          {"self_intersecting_pairs",
           r.self_intersections_checked ? io::Json(r.self_intersecting_pairs) : io::Json(nullptr)}};
}

int run(const Options& o) {
  cad::ImportSettings s;
  s.unit = parse_unit(o.unit);
  s.deflection_mm = o.deflection;
  s.angular_deflection_rad = o.angular;
  s.part = o.part;
  s.reader.timeout_s = o.timeout;
  s.reader.memory_mib = o.memory;
  s.repair.repair = !o.no_repair;
  s.repair.fill_holes = o.fill_holes;
  s.repair.check_self_intersections = !o.no_self_check;
  const cad::ImportResult r = cad::import_cad(o.input, s);
  const auto& m = r.mesh;
  const Eigen::AlignedBox3f box = m.bbox();
  const Eigen::Vector3f ext = m.extent();

  io::write_mesh(o.output, m,
                 {{"source", o.input},
                  {"unit", "mm"},
                  {"source_unit", unit_name(r.unit) + " (" + r.unit_source + ")"},
                  {"reader", r.reader},
                  {"watertight", r.repair.watertight ? "true" : "false"}});

  io::Json j{{"input", o.input},
             {"output", o.output},
             {"format", r.format},
             {"reader", r.reader},
             {"unit", unit_name(r.unit)},
             {"unit_source", r.unit_source},
             {"unit_note", r.unit_note},
             {"parts", r.parts},
             {"part", o.part.empty() ? io::Json(nullptr) : io::Json(o.part)},
             {"triangles", m.faces.size()},
             {"vertices", m.vertices.size()},
             {"bbox_mm", {ext.x(), ext.y(), ext.z()}},
             {"bbox_min_mm", {box.min().x(), box.min().y(), box.min().z()}},
             {"bbox_max_mm", {box.max().x(), box.max().y(), box.max().z()}},
             {"area_mm2", m.area()},
             {"watertight", r.repair.watertight},
             {"outward_oriented", r.repair.outward},
             {"volume_mm3", r.repair.volume_mm3},
             {"repaired", !o.no_repair},
             {"repair", repair_json(r.repair)},
             {"warnings", r.warnings},
             {"timings_s", {{"read", r.read_seconds}, {"repair", r.repair_seconds}}}};
  std::ostringstream h;
  h << "imported " << o.input << " (" << r.format << " via " << r.reader << ")\n"
    << "  unit      " << unit_name(r.unit) << " [" << r.unit_source << ": " << r.unit_note << "]\n"
    << "  mesh      " << m.faces.size() << " triangles, " << m.vertices.size() << " vertices\n"
    << "  bbox      " << ext.x() << " x " << ext.y() << " x " << ext.z() << " mm\n"
    << "  watertight " << (r.repair.watertight ? "yes" : "no") << " (holes " << r.repair.holes
    << ", non-manifold edges " << r.repair.non_manifold_edges << ", self-intersecting pairs "
    << r.repair.self_intersecting_pairs << ")\n"
    << "  repaired  " << r.repair.duplicate_vertices_merged << " duplicate vertices merged, "
    << r.repair.degenerate_faces_removed << " degenerate faces removed, "
    << r.repair.faces_reoriented << " faces reoriented\n";
  for (const auto& w : r.warnings) h << "  warning   " << w << "\n";
  h << "  wrote     " << o.output << "\n";
  emit(o.json, j, h.str());
  return 0;
}

}  // namespace

Command add_import(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "import",
      "Read a CAD/mesh file (STL, OBJ, PLY, DAE, glTF/GLB, 3MF, ... via assimp; STEP, "
      "IGES via OpenCASCADE), check and repair it, write a millimetre mesh.");
  app->add_option("file", o->input, "input CAD or mesh file")->required();
  app->add_option("-o,--output", o->output, "output mesh (.ply or .stl), millimetres")->required();
  app->add_option("--unit", o->unit,
                  "unit of the file's coordinates: mm|cm|m|in|um|auto (auto: the unit the file "
                  "declares, else a guess from the extent, reported)")
      ->capture_default_str();
  app->add_option("--deflection", o->deflection, "STEP/IGES chordal deflection (mm)")
      ->capture_default_str();
  app->add_option("--angular-deflection", o->angular, "STEP/IGES angular deflection (rad)")
      ->capture_default_str();
  app->add_option("--part", o->part,
                  "import only the part/node with this name (default: merge all)");
  add_reader_limits(*app, o->timeout, o->memory);
  app->add_flag("--no-repair", o->no_repair, "only check and report; write the mesh as read");
  app->add_flag("--fill-holes", o->fill_holes, "triangulate open boundaries");
  app->add_flag("--no-self-check", o->no_self_check,
                "skip the self-intersection test (huge meshes)");
  app->add_flag("--json", o->json, "machine-readable report on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
