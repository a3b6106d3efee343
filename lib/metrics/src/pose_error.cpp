#include "laserfit/metrics/pose_error.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <sstream>

#include "laserfit/core/error.hpp"

namespace laserfit::metrics {

std::vector<Eigen::Matrix3d> Symmetry::rotations(double step_deg) const {
  std::vector<Eigen::Matrix3d> out;
  const int n = kind == Kind::None       ? 1
                : kind == Kind::Discrete ? order
                                         : int(std::ceil(360.0 / step_deg));
  for (int k = 0; k < n; ++k)
    out.push_back(Eigen::AngleAxisd(2 * M_PI * k / n, axis.normalized()).toRotationMatrix());
  return out;
}

std::string Symmetry::describe() const {
  std::ostringstream s;
  const char* name = axis.x() == 1 ? "x" : axis.y() == 1 ? "y" : "z";
  if (kind == Kind::None) s << "none";
  if (kind == Kind::Discrete) s << "discrete " << order << " " << name;
  if (kind == Kind::Continuous) s << "continuous " << name;
  return s.str();
}

Symmetry parse_symmetry(const std::string& text) {
  std::istringstream in(text);
  std::string kind, axis;
  Symmetry s;
  in >> kind;
  auto read_axis = [&] {
    in >> axis;
    if (axis == "x")
      s.axis = Eigen::Vector3d::UnitX();
    else if (axis == "y")
      s.axis = Eigen::Vector3d::UnitY();
    else if (axis == "z")
      s.axis = Eigen::Vector3d::UnitZ();
    else
      throw Error("symmetry '" + text + "': axis must be x, y or z");
  };
  if (kind == "none") {
  } else if (kind == "discrete") {
    s.kind = Symmetry::Kind::Discrete;
    if (!(in >> s.order) || s.order < 2)
      throw Error("symmetry '" + text + "': expected 'discrete N axis', N >= 2");
    read_axis();
  } else if (kind == "continuous") {
    s.kind = Symmetry::Kind::Continuous;
    read_axis();
  } else {
    throw Error("symmetry '" + text + "': expected none, 'discrete N x|y|z' or 'continuous x|y|z'");
  }
  std::string rest;
  if (in >> rest) throw Error("symmetry '" + text + "': unexpected '" + rest + "'");
  return s;
}

PoseError pose_error(const Pose& est, const Pose& gt, const Symmetry& sym,
                     const std::vector<Eigen::Vector3f>& model) {
  PoseError best;
  best.t_mm = (est.translation() - gt.translation()).norm();  // the axis passes through the origin
  best.r_deg = best.mssd_mm = std::numeric_limits<double>::infinity();
  if (sym.kind == Symmetry::Kind::Continuous) {
    const Eigen::Vector3d a = est.rotation() * sym.axis, b = gt.rotation() * sym.axis;
    best.r_deg = std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
  }
  for (const Eigen::Matrix3d& S : sym.rotations()) {
    Pose G = gt;
    G.linear() = gt.rotation() * S;
    if (sym.kind != Symmetry::Kind::Continuous)
      best.r_deg = std::min(
          best.r_deg,
          Eigen::AngleAxisd(est.rotation().transpose() * G.rotation()).angle() * 180 / M_PI);
    double m = 0;
    for (const auto& x : model)
      m = std::max(m, (est * x.cast<double>() - G * x.cast<double>()).norm());
    best.mssd_mm = std::min(best.mssd_mm, m);
  }
  return best;
}

}  // namespace laserfit::metrics
