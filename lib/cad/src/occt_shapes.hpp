#pragma once
// Small OpenCASCADE modelling vocabulary for the part generators (private to lib/cad).
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Ax2.hxx>

#include "laserfit/core/error.hpp"

namespace laserfit::cad::shapes {

inline TopoDS_Shape box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape();
}
// Cylinder of radius r from point p along unit direction d for length h.
inline TopoDS_Shape cylinder(const gp_Pnt& p, const gp_Dir& d, double r, double h) {
  return BRepPrimAPI_MakeCylinder(gp_Ax2(p, d), r, h).Shape();
}
inline TopoDS_Shape cone(const gp_Pnt& p, const gp_Dir& d, double r1, double r2, double h) {
  return BRepPrimAPI_MakeCone(gp_Ax2(p, d), r1, r2, h).Shape();
}
inline TopoDS_Shape sphere(const gp_Pnt& c, double r) {
  return BRepPrimAPI_MakeSphere(c, r).Shape();
}
inline TopoDS_Shape fuse(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  BRepAlgoAPI_Fuse op(a, b);
  if (!op.IsDone()) throw Error("OpenCASCADE boolean fuse failed");
  return op.Shape();
}
inline TopoDS_Shape cut(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  BRepAlgoAPI_Cut op(a, b);
  if (!op.IsDone()) throw Error("OpenCASCADE boolean cut failed");
  return op.Shape();
}
// Stadium-shaped slot (two half-discs joined by a rectangle) in the xy plane, centred at the
// origin, long axis x, extruded over z in [z0, z1].
inline TopoDS_Shape stadium(double length, double width, double z0, double z1) {
  const double r = width / 2, c = length / 2 - r;
  TopoDS_Shape s = box(-c, -r, z0, c, r, z1);
  s = fuse(s, cylinder(gp_Pnt(-c, 0, z0), gp_Dir(0, 0, 1), r, z1 - z0));
  return fuse(s, cylinder(gp_Pnt(c, 0, z0), gp_Dir(0, 0, 1), r, z1 - z0));
}

}  // namespace laserfit::cad::shapes
