#pragma once
// Parametric CAD of the parts laserfit is about (needle and thread, NIST Task Board 1 parts),
// modelled as B-rep solids with OpenCASCADE and tessellated like an imported STEP file.
// Every part's frame is its insertion frame: origin at the insertion point (eye centre, socket
// mouth, thread tip, plug front), +z the insertion direction, so that a part is inserted when its
// frame coincides with its target's frame.
#include <map>
#include <string>
#include <vector>

#include "laserfit/core/mesh.hpp"

namespace laserfit::cad {

struct ModelParam {
  std::string name;
  double value;      // default
  double min, max;   // accepted range (same unit)
  std::string unit;  // always "mm" for lengths
  std::string help;
};

struct GeneratedPart {
  std::string name;   // file stem, e.g. "usb_a_plug"
  std::string frame;  // where the origin and axes are
  TriMesh mesh;       // mm
};

struct GeneratedModel {
  std::string model;
  std::map<std::string, double> params;  // the values used (defaults + overrides)
  double deflection_mm = 0.0;
  std::vector<GeneratedPart> parts;
};

struct ModelInfo {
  std::string name, description;
  std::vector<ModelParam> params;
};

const std::vector<ModelInfo>& model_catalogue();

// Builds `model` with `overrides` (unknown names or values out of range -> laserfit::Error).
GeneratedModel generate_model(const std::string& model,
                              const std::map<std::string, double>& overrides = {});

// Writes <dir>/<part>.ply for every part (parameters and frame in the PLY header) and
// <dir>/<model>.yaml with the parameters that made them. Returns the files written, in order.
// Output bytes depend only on the model and parameters (`make cad` is reproducible).
std::vector<std::string> write_model(const GeneratedModel& model, const std::string& dir);

}  // namespace laserfit::cad
