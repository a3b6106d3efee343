// The refinement variants by name. A new variant: one refine_<name>.cpp and one line here.
#include <utility>

#include "laserfit/core/error.hpp"
#include "stages.hpp"

namespace laserfit::registration {
namespace {
const std::vector<std::pair<std::string, RefineFn>>& table() {
  static const std::vector<std::pair<std::string, RefineFn>> t = {
      {"paper", refine_point_to_point},  // Algorithm 1 exactly: PCL's ICP
      {"point_to_point", refine_point_to_point},
      {"point_to_plane", refine_point_to_plane},
      {"gicp", refine_gicp},
      {"ndt", refine_ndt},
      {"ceres", refine_ceres},
  };
  return t;
}
}  // namespace

std::vector<std::string> refiner_names() {
  std::vector<std::string> n;
  for (const auto& [name, fn] : table()) n.push_back(name);
  return n;
}

RefineFn find_refiner(const std::string& name) {
  std::string all;
  for (const auto& [n, fn] : table()) {
    if (n == name) return fn;
    all += (all.empty() ? "" : ", ") + n;
  }
  throw Error("unknown registration method '" + name + "' (" + all + ")");
}

}  // namespace laserfit::registration
