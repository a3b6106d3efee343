#pragma once
// CAD import: any mesh format assimp reads (STL, OBJ, PLY, DAE, glTF/GLB, 3MF, ...) and STEP /
// IGES through OpenCASCADE, into one millimetre triangle mesh, checked and repaired.
#include <string>
#include <vector>

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

ImportResult import_cad(const std::string& path, const ImportSettings& settings = {});

// Raw readers (no unit resolution, no repair); used by import_cad and the tests.
struct RawMesh {
  TriMesh mesh;
  std::vector<std::string> parts;
  double declared_to_mm = 0.0;  // > 0 when the file declares its unit (scale to mm)
  std::string declared_unit;    // as written in the file, e.g. "MM", "meter=0.001", "m (glTF)"
  std::vector<std::string> warnings;
};
RawMesh read_with_assimp(const std::string& path, const std::string& part);
RawMesh read_with_occt(const std::string& path, const ImportSettings& settings);

}  // namespace laserfit::cad
