#include "laserfit/core/pose.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "laserfit/core/error.hpp"

namespace laserfit {

Pose pose_from_tq(const Eigen::Vector3d& t_mm, const Eigen::Quaterniond& q) {
  Pose T = Pose::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t_mm;
  return T;
}

Pose parse_pose(const std::string& text, const std::string& what) {
  std::string s = text;
  for (char& c : s)
    if (c == ',' || c == '[' || c == ']' || c == ';') c = ' ';
  std::istringstream in(s);
  std::vector<double> v;
  std::string tok;
  while (in >> tok) {
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(x))
      throw Error(what, "not a finite number: '" + tok + "'");
    v.push_back(x);
  }
  if (v.size() == 7) {
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw Error(
          what, "quaternion (w,x,y,z) is not unit length (|q| = " + std::to_string(q.norm()) + ")");
    return pose_from_tq({v[0], v[1], v[2]}, q);
  }
  if (v.size() == 16) {
    Eigen::Matrix4d M;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) M(r, c) = v[4 * r + c];
    const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
    if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-4 || R.determinant() < 0 ||
        M.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
      throw Error(what, "4x4 matrix is not a rigid transform");
    Pose T = Pose::Identity();
    T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
    T.translation() = M.topRightCorner<3, 1>();
    return T;
  }
  throw Error(what, "expected 7 numbers 'x y z qw qx qy qz' (mm) or 16 (4x4 row-major), got " +
                        std::to_string(v.size()));
}

std::array<double, 7> pose_to_tq(const Pose& T) {
  Eigen::Quaterniond q(T.rotation());
  if (q.w() < 0) q.coeffs() *= -1.0;
  const auto& t = T.translation();
  return {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
}

std::string pose_to_string(const Pose& T) {
  std::ostringstream out;
  out.precision(17);
  const auto v = pose_to_tq(T);
  for (size_t i = 0; i < v.size(); ++i) out << (i ? " " : "") << v[i];
  return out.str();
}

double rotation_angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.normalized().angularDistance(b.normalized());
}

Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
             const Eigen::Vector3d& x_hint) {
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = x_hint - x_hint.dot(z) * z;
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  Pose T = Pose::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = z.cross(x);
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

}  // namespace laserfit
