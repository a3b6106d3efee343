#pragma once
// Everything that defines a simulated scan. Defaults: Micro-Epsilon LLT3000-25 class sensor on a
// Franka Panda; every value can be overridden in the scene file.
#include <Eigen/Core>
#include <array>
#include <string>

#include "laserfit/core/pose.hpp"
#include "laserfit/sensor/line_scanner.hpp"

namespace laserfit::scan {

struct SweepSettings {
  Pose T_base_sensor_start = Pose::Identity();  // nominal sensor pose at the first profile
  Eigen::Vector3d direction = {0, 1, 0};        // sweep direction in the sensor frame (unit)
  double length_mm = 10.0;                      // sweep length
  double speed_mm_s = 10.0;                     // sweep speed
  double profile_rate_hz = 1000.0;              // profiles per second (LLT3000: up to 10 kHz)
  int profiles() const;                         // floor(length / spacing) + 1
  double spacing_mm() const { return speed_mm_s / profile_rate_hz; }
};

// Measurement noise and artefacts of the sensor; each switchable (0 disables it).
struct NoiseSettings {
  bool enabled = true;
  double depth_sigma_um = 1.5;  // along the laser ray at normal incidence; / cos(incidence)
  double x_jitter_um = 1.0;     // along the profile
  double z_quantum_um = 25000.0 / 65536.0;  // 16-bit depth over the 25 mm range (0.38 um)
  double speckle_sigma_um = 1.0;            // speckle: correlated along the profile (AR(1))
  double speckle_corr_um = 50.0;            //   correlation length along x
  double dropout_rate = 0.001;              // low-signal dropouts anywhere
  double grazing_start_deg = 60.0;          // dropout probability rises to 1 at max_incidence_deg
  double mixed_pixel_prob = 0.5;            // at a depth discontinuity, chance of a mixed pixel
  double mixed_pixel_jump_mm = 0.05;        //   what counts as a discontinuity between neighbours
  double outlier_rate = 5e-4;   // specular / multipath outliers, on shiny materials only
  double outlier_max_mm = 1.0;  //   displacement along the ray, uniform in +-max
  double bias_sigma_um = 2.0;   // per-scan depth bias (drawn once per scan)
};

// Motion of the carrying arm during the sweep.
struct MotionSettings {
  bool enabled = true;
  double offset_sigma_mm = 0.1;  // rigid error of the whole sweep (Panda repeatability)
  double offset_sigma_deg = 0.005;
  double jitter_sigma_mm = 0.002;  // smooth per-profile deviation during the sweep (AR(1))
  double jitter_sigma_deg = 0.0005;
  double jitter_corr_profiles = 50;  //   correlation length in profiles
  // Fixed sensor-to-flange calibration error [x y z mm, rx ry rz deg], applied in the sensor frame.
  std::array<double, 6> calibration_error = {0, 0, 0, 0, 0, 0};
};

struct ScanSettings {
  sensor::LineScannerGeometry sensor;
  SweepSettings sweep;
  NoiseSettings noise;
  MotionSettings motion;
  void validate(const std::string& what) const;  // throws laserfit::Error naming `what`
};

}  // namespace laserfit::scan
