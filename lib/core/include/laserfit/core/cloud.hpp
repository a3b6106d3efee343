#pragma once
// Point cloud with optional normals, floats in millimetres. An organized cloud (a laser scan:
// width = points per profile, height = profiles) keeps invalid points as NaN so that the grid
// structure survives; an unorganized one has height 1.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace laserfit {

struct PointCloud {
  std::vector<Eigen::Vector3f> points;   // mm
  std::vector<Eigen::Vector3f> normals;  // unit, empty when not known
  std::vector<int32_t> labels;           // per point (e.g. which object), empty when not known
  int width = 0;                         // points per row (organized) or size (unorganized)
  int height = 1;                        // rows; 1 for unorganized
  // Where the sensor was, in the cloud's frame (mm; PCL's sensor_origin_): a scan's normals face
  // it. Written to and read from the file header as "laserfit.viewpoint x y z".
  std::optional<Eigen::Vector3d> sensor_origin;
  // Provenance written into the file header (source, unit, seed ...).
  std::map<std::string, std::string> metadata;

  size_t size() const { return points.size(); }
  bool has_normals() const { return !normals.empty(); }
  bool organized() const { return height > 1; }
};

}  // namespace laserfit
