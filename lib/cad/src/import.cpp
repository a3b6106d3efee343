#include "laserfit/cad/import.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/io/header_check.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::cad {
namespace {

bool is_brep(const std::string& ext) {
  return ext == "step" || ext == "stp" || ext == "iges" || ext == "igs";
}

// "the STEP reader", "the IGES reader", "the assimp OBJ reader": what a message names.
std::string reader_name(const std::string& format) {
  std::string upper = format;
  for (auto& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (format == "step" || format == "stp") return "the STEP reader";
  if (format == "iges" || format == "igs") return "the IGES reader";
  return "the assimp " + (upper.empty() ? std::string("mesh") : upper) + " reader";
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Decide how to read the raw coordinates: the user's word first, then what the file declares,
// then a guess from the extent (reported, because a guess can be wrong).
void resolve_unit(const ImportSettings& s, const RawMesh& raw, ImportResult& r) {
  const double largest = raw.mesh.extent().maxCoeff();
  if (s.unit != Unit::Auto) {
    r.unit = s.unit;
    r.unit_source = "user";
    r.unit_note = "--unit " + unit_name(s.unit);
    if (raw.declared_to_mm > 0 && std::abs(raw.declared_to_mm - unit_to_mm(s.unit)) > 1e-12)
      r.warnings.push_back("file declares '" + raw.declared_unit + "' but --unit " +
                           unit_name(s.unit) + " overrides it");
    return;
  }
  if (raw.declared_to_mm > 0) {
    r.unit_source = "file";
    r.unit_note = raw.declared_unit;
    r.unit = std::abs(raw.declared_to_mm - 1.0) < 1e-12     ? Unit::Millimetre
             : std::abs(raw.declared_to_mm - 1000.0) < 1e-9 ? Unit::Metre
             : std::abs(raw.declared_to_mm - 25.4) < 1e-9   ? Unit::Inch
             : std::abs(raw.declared_to_mm - 10.0) < 1e-12  ? Unit::Centimetre
                                                            : Unit::Millimetre;
    return;
  }
  r.unit = guess_unit_from_extent(largest);
  r.unit_source = "guess";
  std::ostringstream note;
  note << "no unit in " << r.format << " file; largest side " << largest << " -> guessed "
       << unit_name(r.unit) << " (override with --unit)";
  r.unit_note = note.str();
}

}  // namespace

ImportResult import_cad_uncached(const std::string& path, const ImportSettings& s) {
  require_input_file(path);
  if (!(s.deflection_mm > 0) || !std::isfinite(s.deflection_mm))
    throw Error(path, "--deflection must be a positive length in mm");
  if (!(s.angular_deflection_rad > 0) || !std::isfinite(s.angular_deflection_rad))
    throw Error(path, "--angular-deflection must be a positive angle in rad");

  ImportResult r;
  r.format = io::lower_extension(path);
  if (!r.format.empty()) r.format.erase(0, 1);  // "step", not ".step"
  io::check_mesh_header(path, "." + r.format, s.max_triangles);
  const auto t0 = std::chrono::steady_clock::now();
  RawMesh raw;
  if (is_brep(r.format)) {
    r.reader = "opencascade";
    raw = read_isolated(path, reader_name(r.format), s.reader,
                        [&] { return read_with_occt(path, s); });
  } else {
    r.reader = "assimp";
    raw = read_isolated(path, reader_name(r.format), s.reader,
                        [&] { return read_with_assimp(path, s.part); });
  }
  if (raw.mesh.faces.size() > s.max_triangles)
    throw Error(path, std::to_string(raw.mesh.faces.size()) +
                          " triangles, more than the limit of " + std::to_string(s.max_triangles));
  r.read_seconds = seconds_since(t0);
  r.parts = raw.parts;
  r.warnings = raw.warnings;
  if (raw.mesh.empty()) throw Error(path, "no triangles in file");

  resolve_unit(s, raw, r);
  // Raw coordinates -> mm. OpenCASCADE hands STEP/IGES geometry over already converted to mm
  // (factor declared_to_mm applied); assimp hands over the file's numbers untouched.
  const double applied = is_brep(r.format) && raw.declared_to_mm > 0 ? raw.declared_to_mm : 1.0;
  const double scale =
      r.unit_source == "file" ? raw.declared_to_mm / applied : unit_to_mm(r.unit) / applied;
  if (scale != 1.0) raw.mesh.scale(static_cast<float>(scale));

  const auto t1 = std::chrono::steady_clock::now();
  r.repair = check_and_repair(raw.mesh, s.repair, path);
  r.repair_seconds = seconds_since(t1);
  r.mesh = std::move(raw.mesh);
  return r;
}

}  // namespace laserfit::cad
