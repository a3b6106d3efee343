#include "laserfit/cad/generator.hpp"

#include <Standard_Failure.hxx>

#include <functional>
#include <sstream>

#include "laserfit/cad/occt_mesh.hpp"
#include "laserfit/core/error.hpp"
#include "parts.hpp"

namespace laserfit::cad {
namespace {

struct Entry {
  ModelInfo info;
  double deflection_mm;
  std::function<std::vector<PartShape>(const Params&)> build;
};

// Dimensions: sewing needle as in the paper (eye 300-350 um wide, 150 um thread); NIST Assembly
// Task Board 1 parts (USB-A shell 12.0 x 4.5 mm per the USB 2.0 spec, 8 mm pegs).
const std::vector<Entry>& entries() {
  static const std::vector<Entry> e = {
      {{"needle",
        "sewing needle with an elongated eye, and the 150 um thread tip",
        {{"eye_width", 0.32, 0.15, 0.6, "mm", "eye width along its short axis (paper: 0.30-0.35)"},
         {"eye_length", 1.0, 0.3, 3.0, "mm", "eye length along the needle axis"},
         {"shaft_diameter", 0.7, 0.3, 2.0, "mm", "needle shaft diameter"},
         {"length", 35.0, 5.0, 80.0, "mm", "overall needle length"},
         {"head_length", 1.0, 0.2, 5.0, "mm", "from the eye centre to the rounded butt end"},
         {"point_length", 4.0, 0.5, 15.0, "mm", "length of the conical point"},
         {"thread_diameter", 0.15, 0.05, 0.5, "mm", "thread diameter"},
         {"thread_length", 4.0, 0.5, 20.0, "mm", "length of thread modelled behind the tip"},
         {"thread_chamfer", 0.02, 0.0, 0.1, "mm", "radial taper of the cut thread end"}}},
       0.002,
       build_needle},
      {{"usb_a",
        "NIST Task Board 1 USB-A plug and its receptacle",
        {{"shell_width", 12.0, 10.0, 14.0, "mm", "plug shell outer width"},
         {"shell_height", 4.5, 3.5, 6.0, "mm", "plug shell outer height"},
         {"shell_length", 12.0, 8.0, 16.0, "mm", "plug shell length"},
         {"shell_thickness", 0.35, 0.2, 0.6, "mm", "sheet metal thickness"},
         {"body_width", 16.0, 12.5, 25.0, "mm", "overmould width"},
         {"body_height", 8.0, 5.0, 15.0, "mm", "overmould height"},
         {"body_length", 20.0, 5.0, 40.0, "mm", "overmould length"},
         {"clearance", 0.1, 0.0, 1.0, "mm", "receptacle opening minus plug shell (total)"},
         {"socket_depth", 12.0, 8.0, 16.0, "mm", "receptacle cavity depth"},
         {"plate_size", 30.0, 20.0, 60.0, "mm", "square task-board plate around the socket"}}},
       0.005,
       build_usb_a},
      {{"round_peg",
        "NIST Task Board 1 round peg and its hole",
        {{"diameter", 8.0, 2.0, 20.0, "mm", "peg diameter"},
         {"length", 30.0, 5.0, 60.0, "mm", "peg length"},
         {"chamfer", 0.5, 0.0, 2.0, "mm", "peg tip and hole entry chamfer"},
         {"clearance", 0.1, 0.0, 1.0, "mm", "hole diameter minus peg diameter"},
         {"hole_depth", 15.0, 3.0, 40.0, "mm", "blind hole depth"},
         {"block_size", 20.0, 10.0, 60.0, "mm", "square block holding the hole"}}},
       0.005,
       build_round_peg},
      {{"square_peg",
        "NIST Task Board 1 square peg and its hole",
        {{"side", 8.0, 2.0, 20.0, "mm", "peg side"},
         {"length", 30.0, 5.0, 60.0, "mm", "peg length"},
         {"chamfer", 0.5, 0.0, 2.0, "mm", "peg tip chamfer"},
         {"clearance", 0.1, 0.0, 1.0, "mm", "hole side minus peg side"},
         {"hole_depth", 15.0, 3.0, 40.0, "mm", "blind hole depth"},
         {"block_size", 20.0, 10.0, 60.0, "mm", "square block holding the hole"}}},
       0.005,
       build_square_peg},
  };
  return e;
}

}  // namespace

const std::vector<ModelInfo>& model_catalogue() {
  static const std::vector<ModelInfo> c = [] {
    std::vector<ModelInfo> v;
    for (const auto& e : entries()) v.push_back(e.info);
    return v;
  }();
  return c;
}

GeneratedModel generate_model(const std::string& model, const std::map<std::string, double>& ov) {
  const Entry* entry = nullptr;
  for (const auto& e : entries())
    if (e.info.name == model) entry = &e;
  if (!entry) {
    std::string names;
    for (const auto& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
    throw Error("unknown CAD model '" + model + "' (models: " + names + ")");
  }
  GeneratedModel out;
  out.model = model;
  out.deflection_mm = entry->deflection_mm;
  for (const auto& p : entry->info.params) out.params[p.name] = p.value;
  for (const auto& [name, value] : ov) {
    const std::string& wanted = name;  // C++17: a structured binding cannot be captured
    auto it = std::find_if(entry->info.params.begin(), entry->info.params.end(),
                           [&](const ModelParam& p) { return p.name == wanted; });
    if (it == entry->info.params.end()) throw Error(model + ": unknown parameter '" + name + "'");
    if (!(value >= it->min && value <= it->max)) {
      std::ostringstream m;
      m << model << ": " << name << " = " << value << " " << it->unit << " is outside [" << it->min
        << ", " << it->max << "]";
      throw Error(m.str());
    }
    out.params[name] = value;
  }
  try {
    for (auto& ps : entry->build(out.params)) {
      GeneratedPart part{ps.name, ps.frame, tessellate(ps.shape, {entry->deflection_mm, 0.1})};
      if (part.mesh.empty()) throw Error(model + ": part '" + ps.name + "' came out empty");
      out.parts.push_back(std::move(part));
    }
  } catch (const Standard_Failure& e) {
    throw Error(model + ": OpenCASCADE modelling failed: " + e.GetMessageString());
  }
  return out;
}

}  // namespace laserfit::cad
