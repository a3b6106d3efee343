#pragma once
// CAD import: any mesh format assimp reads (STL, OBJ, PLY, DAE, glTF/GLB, 3MF, ...) and STEP /
// IGES through OpenCASCADE, into one millimetre triangle mesh, checked and repaired.
#include <string>
#include <vector>

#include "laserfit/cad/isolate.hpp"
#include "laserfit/cad/repair.hpp"
#include "laserfit/core/mesh.hpp"
#include "laserfit/core/units.hpp"

namespace laserfit::cad {

struct ImportSettings {
  Unit unit = Unit::Auto;       // unit of the file's coordinates; Auto: the file's own, else guess
  double deflection_mm = 0.01;  // STEP/IGES chordal deflection of the tessellation (mm)
  double angular_deflection_rad = 0.2;  // STEP/IGES angular deflection (rad)
  std::string part;                     // select one part/node by name; empty: merge all parts
  RepairSettings repair;
  IsolationLimits reader;             // the parser runs in a child process under these limits
  size_t max_triangles = 50'000'000;  // larger meshes are refused (a 1 GB STL holds 20 M)
};

struct ImportResult {
  TriMesh mesh;                    // millimetres
  std::string format;              // "stl", "step", ...
  std::string reader;              // "assimp" or "opencascade"
  Unit unit = Unit::Millimetre;    // unit the raw coordinates were read in
  std::string unit_source;         // "file" (declared), "user" (--unit) or "guess" (from extent)
  std::string unit_note;           // what was declared / why the guess
  std::vector<std::string> parts;  // part names found in the file
  std::vector<std::string> warnings;
  RepairReport repair;
  double read_seconds = 0.0, repair_seconds = 0.0;
};

// Results are memoised per process by the file's bytes and the settings (the last 32 files): a
// benchmark or a scene list that names one mesh many times reads and repairs it once. Errors
// are not memoised.
ImportResult import_cad(const std::string& path, const ImportSettings& settings = {});
ImportResult import_cad_uncached(const std::string& path, const ImportSettings& settings = {});

// Raw readers (no unit resolution, no repair, no isolation); import_cad runs them through
// read_isolated.
RawMesh read_with_assimp(const std::string& path, const std::string& part);
RawMesh read_with_occt(const std::string& path, const ImportSettings& settings);

}  // namespace laserfit::cad
