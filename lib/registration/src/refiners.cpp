// The refinement variants and the methods. A new refiner: one refine_<name>.cpp, one enum value
// (settings.hpp) and one line here.
#include "laserfit/core/error.hpp"
#include "stages.hpp"

namespace laserfit::registration {

RefineFn refiner_fn(Refiner r) {
  switch (r) {
    case Refiner::PointToPoint:
      return refine_point_to_point;
    case Refiner::PointToPlane:
      return refine_point_to_plane;
    case Refiner::Gicp:
      return refine_gicp;
    case Refiner::Ndt:
      return refine_ndt;
    case Refiner::Ceres:
      return refine_ceres;
  }
  throw Error("invalid refiner value");
}

void apply_method(RegistrationSettings& s, Method m) {
  s.policies.paper = m == Method::Paper;
  if (m == Method::Paper) {
    s.coarse.method = CoarseMethod::Pcl;  // Algorithm 1 exactly: PCL's RANSAC and ICP
    s.refine.method = Refiner::PointToPoint;
    return;
  }
  s.refine.method = m == Method::PointToPoint   ? Refiner::PointToPoint
                    : m == Method::PointToPlane ? Refiner::PointToPlane
                    : m == Method::Gicp         ? Refiner::Gicp
                    : m == Method::Ndt          ? Refiner::Ndt
                                                : Refiner::Ceres;
}

Method method_of(const RegistrationSettings& s) {
  if (s.policies.paper) return Method::Paper;
  switch (s.refine.method) {
    case Refiner::PointToPoint:
      return Method::PointToPoint;
    case Refiner::PointToPlane:
      return Method::PointToPlane;
    case Refiner::Gicp:
      return Method::Gicp;
    case Refiner::Ndt:
      return Method::Ndt;
    case Refiner::Ceres:
      break;
  }
  return Method::Ceres;
}

}  // namespace laserfit::registration
