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
  if (points_per_profile < 2 || points_per_profile > 1 << 16)
    bad("points_per_profile must be 2..65536");
  if (!(z_min_mm > 0) || !(z_max_mm > z_min_mm)) bad("need 0 < z_min_mm < z_max_mm");
  if (!(width_mid_mm > 0)) bad("width_mid_mm must be positive");
  if (!(triangulation_angle_deg > 0 && triangulation_angle_deg < 80))
    bad("triangulation_angle_deg must be in (0, 80)");
  if (!(max_incidence_deg > 0 && max_incidence_deg <= 90))
    bad("max_incidence_deg must be in (0, 90]");
  if (!(max_camera_angle_deg > 0 && max_camera_angle_deg <= 90))
    bad("max_camera_angle_deg must be in (0, 90]");
}

Eigen::Vector3d LineScannerGeometry::ray_direction(int j) const {
  const double h = half_fan_rad();
  const double a = -h + 2.0 * h * j / (points_per_profile - 1);
  return {std::sin(a), 0.0, std::cos(a)};
}

const char* visibility_name(Visibility v) {
  switch (v) {
    case Visibility::Visible:
      return "visible";
    case Visibility::OutOfRange:
      return "out_of_range";
    case Visibility::OutsideFan:
      return "outside_fan";
    case Visibility::Grazing:
      return "grazing";
    case Visibility::LaserShadow:
      return "laser_shadow";
    case Visibility::CameraShadow:
      return "camera_shadow";
  }
  return "?";
}

LineScannerView::LineScannerView(const Pose& T, const LineScannerGeometry& g, bool swept)
    : T_scene_sensor_(T),
      T_sensor_scene_(T.inverse()),
      g_(g),
      swept_(swept),
      tan_half_fan_(std::tan(g.half_fan_rad())),
      baseline_(g.baseline_mm()),
      cos_max_incidence_(static_cast<float>(std::cos(g.max_incidence_deg * M_PI / 180.0))),
      cos_max_camera_(static_cast<float>(std::cos(g.max_camera_angle_deg * M_PI / 180.0))) {}

Eigen::Vector3f LineScannerView::camera_in_scene(double y) const {
  return (T_scene_sensor_ * Eigen::Vector3d(0, y + baseline_, 0)).cast<float>();
}

Visibility LineScannerView::visibility(const raycast::Scene& scene, const Eigen::Vector3f& p,
                                       const Eigen::Vector3f& n) const {
  const Eigen::Vector3d ps = T_sensor_scene_ * p.cast<double>();
  if (ps.z() < g_.z_min_mm || ps.z() > g_.z_max_mm) return Visibility::OutOfRange;
  if (std::abs(ps.x()) > ps.z() * tan_half_fan_) return Visibility::OutsideFan;
  const double y = swept_ ? ps.y() : 0.0;
  const Eigen::Vector3f emitter = (T_scene_sensor_ * Eigen::Vector3d(0, y, 0)).cast<float>();
  const Eigen::Vector3f camera = camera_in_scene(y);
  if (n.dot((emitter - p).normalized()) < cos_max_incidence_) return Visibility::Grazing;
  if (!camera_angle_ok(p, n, camera)) return Visibility::CameraShadow;
  const float eps = kSelfShadowEps_mm;
  if (!scene.segment_clear(p + eps * n, emitter, eps)) return Visibility::LaserShadow;
  if (!scene.segment_clear(p + eps * n, camera, eps)) return Visibility::CameraShadow;
  return Visibility::Visible;
}

}  // namespace laserfit::sensor
