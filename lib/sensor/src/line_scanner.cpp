#include "laserfit/sensor/line_scanner.hpp"

#include <cmath>

#include "laserfit/core/error.hpp"

namespace laserfit::sensor {

double LineScannerGeometry::half_fan_rad() const { return std::atan(0.5 * width_mid_mm / z_mid()); }

double LineScannerGeometry::baseline_mm() const {
  return z_mid() * std::tan(triangulation_angle_deg * M_PI / 180.0);
}

void LineScannerGeometry::validate(const std::string& what) const {
  auto bad = [&](const std::string& m) { throw Error(what, "sensor: " + m); };
  if (points_per_profile < 2 || points_per_profile > 1 << 16) bad("points_per_profile must be 2..65536");
  if (!(z_min_mm > 0) || !(z_max_mm > z_min_mm)) bad("need 0 < z_min_mm < z_max_mm");
  if (!(width_mid_mm > 0)) bad("width_mid_mm must be positive");
  if (!(triangulation_angle_deg > 0 && triangulation_angle_deg < 80)) bad("triangulation_angle_deg must be in (0, 80)");
  if (!(max_incidence_deg > 0 && max_incidence_deg <= 90)) bad("max_incidence_deg must be in (0, 90]");
  if (!(max_camera_angle_deg > 0 && max_camera_angle_deg <= 90)) bad("max_camera_angle_deg must be in (0, 90]");
}

const char* visibility_name(Visibility v) {
  switch (v) {
    case Visibility::Visible: return "visible";
    case Visibility::OutOfRange: return "out_of_range";
    case Visibility::OutsideFan: return "outside_fan";
    case Visibility::Grazing: return "grazing";
    case Visibility::LaserShadow: return "laser_shadow";
    case Visibility::CameraShadow: return "camera_shadow";
  }
  return "?";
}

Eigen::Vector3d camera_position(const LineScannerGeometry& g, double y) {
  return {0.0, y + g.baseline_mm(), 0.0};
}

Visibility line_scanner_visibility(const raycast::Scene& scene, const Pose& T_scene_sensor,
                                   const LineScannerGeometry& g, const Eigen::Vector3f& p,
                                   const Eigen::Vector3f& n, bool swept) {
  const Eigen::Vector3d ps = T_scene_sensor.inverse() * p.cast<double>();
  if (ps.z() < g.z_min_mm || ps.z() > g.z_max_mm) return Visibility::OutOfRange;
  if (std::abs(std::atan2(ps.x(), ps.z())) > g.half_fan_rad()) return Visibility::OutsideFan;
  const double y = swept ? ps.y() : 0.0;
  const Eigen::Vector3f emitter = (T_scene_sensor * Eigen::Vector3d(0, y, 0)).cast<float>();
  const Eigen::Vector3f camera = (T_scene_sensor * camera_position(g, y)).cast<float>();

  const Eigen::Vector3f to_laser = (emitter - p).normalized();
  const Eigen::Vector3f to_camera = (camera - p).normalized();
  const float cos_laser = n.dot(to_laser), cos_cam = n.dot(to_camera);
  if (cos_laser < std::cos(g.max_incidence_deg * M_PI / 180.0)) return Visibility::Grazing;
  if (cos_cam < std::cos(g.max_camera_angle_deg * M_PI / 180.0)) return Visibility::CameraShadow;
  // A few micrometres of slack so the surface the point lies on does not shadow itself.
  const float eps = 2e-3f;
  if (!scene.segment_clear(p + eps * n, emitter, eps)) return Visibility::LaserShadow;
  if (!scene.segment_clear(p + eps * n, camera, eps)) return Visibility::CameraShadow;
  return Visibility::Visible;
}

}  // namespace laserfit::sensor
