#pragma once
// Choices are enums inside and names only at the edges (CLI, YAML, JSON): one table of names per
// enum, one parse and one name function over it. An enum opts in by specialising EnumNames:
//
//   template <> struct EnumNames<Refiner> {
//     static constexpr const char* what = "refiner";
//     static constexpr std::pair<Refiner, const char*> table[] = {{Refiner::Ceres, "ceres"}, ...};
//   };
#include <string>
#include <utility>
#include <vector>

#include "laserfit/core/error.hpp"

namespace laserfit {

template <class E>
struct EnumNames;  // what (for messages) and table (every value once, with its name)

template <class E>
const char* name_of(E value) {
  for (const auto& [v, n] : EnumNames<E>::table)
    if (v == value) return n;
  return "?";  // unreachable for a value of the table
}

// Every name, in table order (for --help and error messages).
template <class E>
std::vector<std::string> names_of() {
  std::vector<std::string> out;
  for (const auto& [v, n] : EnumNames<E>::table) out.push_back(n);
  return out;
}

// The value named `text`; throws Error "unknown <what> 'text' (a, b, c)".
template <class E>
E parse_enum(const std::string& text) {
  std::string all;
  for (const auto& [v, n] : EnumNames<E>::table) {
    if (text == n) return v;
    all += (all.empty() ? "" : ", ") + std::string(n);
  }
  throw Error("unknown " + std::string(EnumNames<E>::what) + " '" + text + "' (" + all + ")");
}

}  // namespace laserfit
