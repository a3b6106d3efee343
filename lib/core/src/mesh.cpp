#include "laserfit/core/mesh.hpp"

namespace laserfit {

Eigen::AlignedBox3f TriMesh::bbox() const {
  Eigen::AlignedBox3f box;
  for (const auto& f : faces)
    for (int k = 0; k < 3; ++k) box.extend(vertices[f[k]]);
  return box;
}

Eigen::Vector3f TriMesh::extent() const {
  const auto box = bbox();
  return box.isEmpty() ? Eigen::Vector3f::Zero() : Eigen::Vector3f(box.sizes());
}

Eigen::Vector3f TriMesh::face_normal(int f) const {
  const auto& t = faces[f];
  const Eigen::Vector3f n =
      (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  const float len = n.norm();
  return len > 0.f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
}

double TriMesh::face_area(int f) const {
  const auto& t = faces[f];
  const Eigen::Vector3d a = vertices[t[0]].cast<double>(), b = vertices[t[1]].cast<double>(),
                        c = vertices[t[2]].cast<double>();
  return 0.5 * (b - a).cross(c - a).norm();
}

double TriMesh::area() const {
  double sum = 0.0;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) sum += face_area(f);
  return sum;
}

void TriMesh::append(const TriMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  faces.reserve(faces.size() + other.faces.size());
  for (const auto& f : other.faces) faces.emplace_back(f.array() + offset);
}

void TriMesh::transform(const Eigen::Affine3f& T) {
  for (auto& v : vertices) v = T * v;
  if (T.linear().determinant() < 0.f)  // a mirror flips winding; keep normals outward
    for (auto& f : faces) std::swap(f[1], f[2]);
}

void TriMesh::scale(float s) {
  for (auto& v : vertices) v *= s;
}

}  // namespace laserfit
