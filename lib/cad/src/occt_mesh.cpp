#include "laserfit/cad/occt_mesh.hpp"

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>

namespace laserfit::cad {

TriMesh tessellate(const TopoDS_Shape& shape, const TessellationSettings& s,
                   size_t* faces_skipped) {
  BRepMesh_IncrementalMesh mesher(shape, s.deflection_mm, /*isRelative=*/false,
                                  s.angular_deflection_rad, /*isInParallel=*/false);
  TriMesh out;
  size_t skipped = 0;
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
    const TopoDS_Face& face = TopoDS::Face(ex.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    if (tri.IsNull()) {
      ++skipped;
      continue;
    }
    const gp_Trsf trsf = loc.Transformation();
    const int offset = static_cast<int>(out.vertices.size());
    for (int i = 1; i <= tri->NbNodes(); ++i) {
      const gp_Pnt p = tri->Node(i).Transformed(trsf);
      out.vertices.emplace_back(static_cast<float>(p.X()), static_cast<float>(p.Y()),
                                static_cast<float>(p.Z()));
    }
    // A REVERSED face has its material on the other side of the surface parametrisation.
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int i = 1; i <= tri->NbTriangles(); ++i) {
      int a, b, c;
      tri->Triangle(i).Get(a, b, c);
      if (reversed) std::swap(b, c);
      out.faces.emplace_back(offset + a - 1, offset + b - 1, offset + c - 1);
    }
  }
  if (faces_skipped) *faces_skipped = skipped;
  return out;
}

}  // namespace laserfit::cad
