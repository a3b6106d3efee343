#pragma once
// Geometry of a laser-triangulation line scanner (defaults: Micro-Epsilon LLT3000-25 class) and
// the visibility rule shared by the scan simulator and view-dependent reference clouds.
//
// Sensor frame: origin at the laser emitter; z along the laser axis (measuring direction);
// x along the projected line (the 2048-point profile); y normal to the laser plane, the sweep
// direction. The camera sits at +y, `baseline` away, looking back at the laser plane.
#include <Eigen/Core>
#include <string>

#include "laserfit/core/pose.hpp"
#include "laserfit/raycast/scene.hpp"

namespace laserfit::sensor {

struct LineScannerGeometry {
  int points_per_profile = 2048;        // samples across the line
  double z_min_mm = 77.5;               // start of the measuring range (from the emitter)
  double z_max_mm = 102.5;              // end of the measuring range
  double width_mid_mm = 25.0;           // line length at mid range -> ~12.2 um pitch
  double triangulation_angle_deg = 25;  // laser axis vs. camera axis at mid range
  double max_incidence_deg = 80;        // laser incidence beyond which no usable return
  double max_camera_angle_deg = 80;     // surface seen more obliquely by the camera: no peak

  double z_mid() const { return 0.5 * (z_min_mm + z_max_mm); }
  double half_fan_rad() const;  // fan half-angle from the emitter
  double baseline_mm() const;   // emitter-to-camera distance along +y
  double pitch_mid_mm() const { return width_mid_mm / (points_per_profile - 1); }
  // Unit direction of profile column `j`'s laser ray in the sensor frame (x-z laser plane),
  // equally spaced in angle across the fan.
  Eigen::Vector3d ray_direction(int j) const;
  void validate(const std::string& what) const;  // throws laserfit::Error on nonsense
};

// Offset (mm) off the surface before an occlusion ray starts, so the surface a point lies on
// does not shadow itself; both the scanner and the reference clouds use it.
inline constexpr float kSelfShadowEps_mm = 2e-3f;

// Why a surface point is or is not measured; a scan keeps only `Visible`.
enum class Visibility { Visible, OutOfRange, OutsideFan, Grazing, LaserShadow, CameraShadow };
const char* visibility_name(Visibility v);

// The one visibility rule, for a scanner placed in a scene (T_scene_sensor). `p`, `n` are a
// surface point and its outward normal in the scene frame. For a swept scanner the emitter is
// wherever the sweep puts the laser plane through `p` (sensor origin moved along its y axis); for
// a static one the emitter is the sensor origin. The point is measured when it lies inside the
// measuring range and fan, the laser hits it not too obliquely and unobstructed (laser shadow),
// and the camera sees it unobstructed and not too obliquely (camera shadow). Everything the rule
// needs is precomputed: it runs once or twice per candidate point, millions of times per cloud.
class LineScannerView {
 public:
  LineScannerView(const Pose& T_scene_sensor, const LineScannerGeometry& g, bool swept = true);
  Visibility visibility(const raycast::Scene& scene, const Eigen::Vector3f& p,
                        const Eigen::Vector3f& n) const;
  const Pose& T_scene_sensor() const { return T_scene_sensor_; }
  // Pieces of the rule for the scanner, whose laser ray already found the lit point: the camera
  // position (laser plane at sweep offset y) and the camera viewing-angle test; the camera
  // occlusion ray is cast in batches by the scanner itself (raycast::Scene::segments_clear).
  bool camera_angle_ok(const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                       const Eigen::Vector3f& camera) const {
    return n.dot((camera - p).normalized()) >= cos_max_camera_;
  }
  Eigen::Vector3f camera_in_scene(double y = 0) const;
  float cos_max_incidence() const { return cos_max_incidence_; }

 private:
  Pose T_scene_sensor_, T_sensor_scene_;
  LineScannerGeometry g_;
  bool swept_;
  double tan_half_fan_, baseline_;
  float cos_max_incidence_, cos_max_camera_;
};

}  // namespace laserfit::sensor
