#pragma once
// B-rep -> triangles with OpenCASCADE's BRepMesh. Shared by STEP/IGES import and the parametric
// generator so both tessellate the same way.
#include <TopoDS_Shape.hxx>

#include "laserfit/core/mesh.hpp"

namespace laserfit::cad {

struct TessellationSettings {
  double deflection_mm = 0.01;  // max chordal distance between mesh and surface (mm)
  double angular_deflection_rad = 0.2;
};

// Tessellates every face (serially: the output is then byte-identical run to run) and returns the
// triangles with outward winding. `faces_skipped` counts faces BRepMesh could not triangulate.
TriMesh tessellate(const TopoDS_Shape& shape, const TessellationSettings& s,
                   size_t* faces_skipped = nullptr);

}  // namespace laserfit::cad
