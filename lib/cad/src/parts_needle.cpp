// Sewing needle and thread tip (paper, Section IV: 150 um thread, 300-350 um eye).
#include "laserfit/core/error.hpp"
#include "occt_shapes.hpp"
#include "parts.hpp"

namespace laserfit::cad {

std::vector<PartShape> build_needle(const Params& p) {
  using namespace shapes;
  const double r = p.at("shaft_diameter") / 2, w = p.at("eye_width"), L = p.at("eye_length");
  const double head = p.at("head_length"), tip = p.at("point_length"), len = p.at("length");
  if (w >= p.at("shaft_diameter") - 0.1)
    throw Error("needle: eye_width must leave at least 0.05 mm of wall on each side");
  if (L < w) throw Error("needle: eye_length must be at least eye_width");
  if (head <= L / 2 + r / 2) throw Error("needle: head_length too short to hold the eye");
  const double shaft_end = len - head - tip;  // x where the conical point starts
  if (shaft_end <= L / 2) throw Error("needle: length too short for head, eye and point");

  // Axis along +x (point at +x), rounded butt at -x, eye through along z.
  TopoDS_Shape needle = cylinder(gp_Pnt(-head + r, 0, 0), gp_Dir(1, 0, 0), r, shaft_end + head - r);
  needle = fuse(needle, sphere(gp_Pnt(-head + r, 0, 0), r));
  needle = fuse(needle, cone(gp_Pnt(shaft_end, 0, 0), gp_Dir(1, 0, 0), r, 0.0, tip));
  // The eye slot: stadium along x through the full thickness.
  needle = cut(needle, stadium(L, w, -2 * r, 2 * r));

  // Thread: axis +z, tip at the origin, body behind it (-z), slightly tapered cut end.
  const double tr = p.at("thread_diameter") / 2, tl = p.at("thread_length");
  const double ch = std::min(p.at("thread_chamfer"), 0.9 * tr);
  const double ch_len = ch > 0 ? 2 * ch : 0.0;
  TopoDS_Shape thread = cylinder(gp_Pnt(0, 0, -tl), gp_Dir(0, 0, 1), tr, tl - ch_len);
  if (ch_len > 0)
    thread = fuse(thread, cone(gp_Pnt(0, 0, -ch_len), gp_Dir(0, 0, 1), tr, tr - ch, ch_len));

  return {
      {"needle",
       "origin at the eye centre; x along the needle towards the point; z through the eye", needle},
      {"thread_tip",
       "origin at the centre of the thread end; z along the thread, pointing out of the tip",
       thread}};
}

}  // namespace laserfit::cad
