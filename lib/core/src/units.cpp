#include "laserfit/core/units.hpp"

#include "laserfit/core/error.hpp"

namespace laserfit {

Unit parse_unit(const std::string& s) {
  if (s == "auto") return Unit::Auto;
  if (s == "mm") return Unit::Millimetre;
  if (s == "cm") return Unit::Centimetre;
  if (s == "m") return Unit::Metre;
  if (s == "in" || s == "inch") return Unit::Inch;
  if (s == "um") return Unit::Micrometre;
  throw Error("unknown unit '" + s + "' (expected mm, cm, m, in, um or auto)");
}

std::string unit_name(Unit u) {
  switch (u) {
    case Unit::Auto:
      return "auto";
    case Unit::Millimetre:
      return "mm";
    case Unit::Centimetre:
      return "cm";
    case Unit::Metre:
      return "m";
    case Unit::Inch:
      return "in";
    case Unit::Micrometre:
      return "um";
  }
  return "?";
}

double unit_to_mm(Unit u) {
  switch (u) {
    case Unit::Millimetre:
      return 1.0;
    case Unit::Centimetre:
      return 10.0;
    case Unit::Metre:
      return 1000.0;
    case Unit::Inch:
      return 25.4;
    case Unit::Micrometre:
      return 1e-3;
    case Unit::Auto:
      break;
  }
  throw Error("unit 'auto' has no scale; resolve it first");
}

Unit guess_unit_from_extent(double largest_side) {
  return largest_side < 1.0 ? Unit::Metre : Unit::Millimetre;
}

}  // namespace laserfit
