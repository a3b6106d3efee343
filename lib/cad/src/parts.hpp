#pragma once
// Part builders (private to lib/cad). Each takes validated parameters (mm) and returns solids.
#include <TopoDS_Shape.hxx>

#include <map>
#include <string>
#include <vector>

namespace laserfit::cad {

using Params = std::map<std::string, double>;
struct PartShape {
  std::string name, frame;
  TopoDS_Shape shape;
};

std::vector<PartShape> build_needle(const Params& p);
std::vector<PartShape> build_usb_a(const Params& p);
std::vector<PartShape> build_round_peg(const Params& p);
std::vector<PartShape> build_square_peg(const Params& p);

}  // namespace laserfit::cad
