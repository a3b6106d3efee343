// NIST Assembly Task Board 1 round and square pegs with their holes.
#include <BRepPrimAPI_MakeWedge.hxx>

#include "laserfit/core/error.hpp"
#include "occt_shapes.hpp"
#include "parts.hpp"

namespace laserfit::cad {
namespace {

const char* kPegFrame = "origin at the centre of the peg tip; z along the peg axis, out of the tip";
const char* kHoleFrame =
    "origin at the centre of the hole mouth on the block's top face; z into the hole";

void check_peg(const Params& p, double size) {
  if (p.at("chamfer") >= size / 4)
    throw Error("peg: chamfer must be under a quarter of the peg size");
  if (p.at("block_size") < size + p.at("clearance") + 2.0)
    throw Error("peg: block_size must leave at least 1 mm of wall around the hole");
}

}  // namespace

std::vector<PartShape> build_round_peg(const Params& p) {
  using namespace shapes;
  const double r = p.at("diameter") / 2, ch = p.at("chamfer"), len = p.at("length");
  const double rh = r + p.at("clearance") / 2, depth = p.at("hole_depth"),
               b = p.at("block_size") / 2;
  check_peg(p, 2 * r);
  if (depth >= 2 * b) throw Error("round_peg: hole_depth must be less than block_size");
  TopoDS_Shape peg = cylinder(gp_Pnt(0, 0, -len), gp_Dir(0, 0, 1), r, len - ch);
  if (ch > 0) peg = fuse(peg, cone(gp_Pnt(0, 0, -ch), gp_Dir(0, 0, 1), r, r - ch, ch));
  TopoDS_Shape block = box(-b, -b, 0, b, b, 2 * b);
  block = cut(block, cylinder(gp_Pnt(0, 0, -0.1), gp_Dir(0, 0, 1), rh, depth + 0.1));
  if (ch > 0)
    block = cut(block, cone(gp_Pnt(0, 0, -0.01), gp_Dir(0, 0, 1), rh + ch + 0.01, rh, ch + 0.01));
  return {{"round_peg", kPegFrame, peg}, {"round_hole", kHoleFrame, block}};
}

std::vector<PartShape> build_square_peg(const Params& p) {
  using namespace shapes;
  const double a = p.at("side") / 2, ch = p.at("chamfer"), len = p.at("length");
  const double ah = a + p.at("clearance") / 2, depth = p.at("hole_depth"),
               b = p.at("block_size") / 2;
  check_peg(p, 2 * a);
  if (depth >= 2 * b) throw Error("square_peg: hole_depth must be less than block_size");
  TopoDS_Shape peg = box(-a, -a, -len, a, a, -ch);
  if (ch > 0) {
    // 45-degree chamfered tip: a frustum (BRepPrimAPI_MakeWedge) whose local y axis is global +z.
    const gp_Ax2 axes(gp_Pnt(-a, a, -ch), gp_Dir(0, -1, 0), gp_Dir(1, 0, 0));
    peg = fuse(
        peg, BRepPrimAPI_MakeWedge(axes, 2 * a, ch, 2 * a, ch, ch, 2 * a - ch, 2 * a - ch).Shape());
  }
  TopoDS_Shape block = box(-b, -b, 0, b, b, 2 * b);
  block = cut(block, box(-ah, -ah, -0.1, ah, ah, depth));
  return {{"square_peg", kPegFrame, peg}, {"square_hole", kHoleFrame, block}};
}

}  // namespace laserfit::cad
