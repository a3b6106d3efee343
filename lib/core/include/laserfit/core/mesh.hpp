#pragma once
// Indexed triangle mesh in millimetres. Floats for geometry (the brief: floats for cloud points;
// a 100 mm part keeps ~6 nm resolution in float), int32 indices.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace laserfit {

struct TriMesh {
  std::vector<Eigen::Vector3f> vertices;  // mm
  std::vector<Eigen::Vector3i> faces;     // counter-clockwise seen from outside

  bool empty() const { return faces.empty(); }
  Eigen::AlignedBox3f bbox() const;
  Eigen::Vector3f extent() const;            // bbox size along x, y, z (mm)
  double area() const;                       // mm^2
  Eigen::Vector3f face_normal(int f) const;  // unit, zero for a degenerate face
  double face_area(int f) const;
  // Appends another mesh (indices shifted), used to merge multi-part files.
  void append(const TriMesh& other);
  void transform(const Eigen::Affine3f& T);
  void scale(float s);
};

}  // namespace laserfit
