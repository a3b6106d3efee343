#pragma once
// Length units. Everything inside laserfit is millimetres; a unit only says how to read a file.
#include <Eigen/Core>
#include <string>

namespace laserfit {

enum class Unit { Auto, Millimetre, Centimetre, Metre, Inch, Micrometre };

Unit parse_unit(const std::string& s);  // "mm", "cm", "m", "in", "um", "auto"; throws Error
std::string unit_name(Unit u);          // "mm", "cm", "m", "in", "um", "auto"
double unit_to_mm(Unit u);              // scale factor; Auto is an error

// Guess the unit of a unitless mesh from its extent (largest bbox side, raw file units):
// parts handled by a cobot gripper are 0.1 mm .. 1 m. A largest side below 1.0 can only be a
// metre file (a sub-millimetre "part" is not something the robot picks); above it, millimetres.
// Inches are never guessed: a 1..40-unit part is as likely mm as in, so ask the user.
Unit guess_unit_from_extent(double largest_side);

}  // namespace laserfit
