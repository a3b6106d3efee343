#include "convert.hpp"

#include <cmath>

namespace laserfit::python {
namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Checks the shape, (N, 3) or (H, W, 3), and the type, float32 or float64.
void check_shape(const py::array& a, const std::string& what, int& width, int& height) {
  if (a.ndim() == 2 && a.shape(1) == 3)
    width = int(a.shape(0)), height = 1;
  else if (a.ndim() == 3 && a.shape(2) == 3)
    width = int(a.shape(1)), height = int(a.shape(0));
  else
    throw py::value_error(what + ": expected an N x 3 or H x W x 3 array");
  if (a.size() == 0) throw py::value_error(what + ": the array is empty");
  if (a.dtype().kind() != 'f') throw py::value_error(what + ": expected float32 or float64");
}

}  // namespace

PointCloud cloud_from_array(const py::array& points, const std::string& what, double to_mm) {
  PointCloud c;
  check_shape(points, what, c.width, c.height);
  const size_t n = size_t(c.width) * size_t(c.height);
  c.points.resize(n);
  c.metadata["unit"] = "mm";
  if (points.dtype().is(py::dtype::of<float>()) && to_mm == 1.0) {  // as stored: one copy
    const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(points);
    const float* p = f.data();
    for (size_t i = 0; i < n; ++i)
      c.points[i] = Eigen::Vector3f(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    return c;
  }
  const Doubles d = Doubles::ensure(points);
  const double* p = d.data();
  for (size_t i = 0; i < n; ++i)  // scaled in double, rounded once (as the file readers do)
    c.points[i] = Eigen::Vector3f(float(p[3 * i] * to_mm), float(p[3 * i + 1] * to_mm),
                                  float(p[3 * i + 2] * to_mm));
  return c;
}

void set_normals(PointCloud& c, const py::array& normals, const std::string& what) {
  int w = 0, h = 0;
  check_shape(normals, what, w, h);
  const Doubles d = Doubles::ensure(normals);
  if (size_t(w) * size_t(h) != c.size())
    throw py::value_error(what + ": " + std::to_string(size_t(w) * h) + " normals for " +
                          std::to_string(c.size()) + " points");
  c.normals.resize(c.size());
  for (size_t i = 0; i < c.size(); ++i)
    c.normals[i] = Eigen::Vector3f(float(d.data()[3 * i]), float(d.data()[3 * i + 1]),
                                   float(d.data()[3 * i + 2]));
}

py::array_t<float> vectors_array(const std::vector<Eigen::Vector3f>& v) {
  py::array_t<float> a({py::ssize_t(v.size()), py::ssize_t(3)});
  float* out = a.mutable_data();
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + k] = v[i][k];
  return a;
}

py::array_t<float> points_array(const PointCloud& c) {
  py::array_t<float> a = vectors_array(c.points);
  if (c.organized()) a.resize({py::ssize_t(c.height), py::ssize_t(c.width), py::ssize_t(3)});
  return a;
}

Pose pose_from_array(const py::array& T, const std::string& what, double to_mm) {
  if (T.ndim() != 2 || T.shape(0) != 4 || T.shape(1) != 4)
    throw py::value_error(what + ": expected a 4 x 4 array");
  const Doubles d = Doubles::ensure(T);
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) M(r, k) = d.data()[4 * r + k];
  if (!M.allFinite()) throw py::value_error(what + ": not finite");
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0 ||
      M.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw py::value_error(what + ": not a rigid transform (rotation and [0 0 0 1] last row)");
  Pose P = Pose::Identity();
  P.linear() = R;
  P.translation() = M.topRightCorner<3, 1>() * to_mm;
  return P;
}

py::array_t<double> pose_array(const Pose& T) {
  py::array_t<double> a({4, 4});
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) a.mutable_at(r, k) = T.matrix()(r, k);
  return a;
}

Eigen::Vector3d vector3_from(const py::object& v, const std::string& what, double to_mm) {
  const Doubles d = Doubles::ensure(v);
  if (!d || d.size() != 3) throw py::value_error(what + ": expected 3 numbers (x, y, z)");
  const Eigen::Vector3d out(d.data()[0], d.data()[1], d.data()[2]);
  if (!out.allFinite()) throw py::value_error(what + ": not finite");
  return out * to_mm;
}

}  // namespace laserfit::python
