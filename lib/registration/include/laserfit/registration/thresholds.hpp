#pragma once
// Tuned registration thresholds (`laserfit tune` writes them, the controller and
// `laserfit register --thresholds` read them). The file (YAML, schema laserfit.thresholds/1)
// gives every value with its unit and says where it came from: the benchmark, its seed and the
// held-out success rate it achieved. The loader is strict: an unknown or missing key, a wrong
// unit or an out-of-range value is an error naming the file.
#include <cstdint>
#include <map>
#include <string>

#include "laserfit/registration/registration.hpp"

namespace laserfit::registration {

struct Thresholds {
  // The parameters the tuning searches, an overlay on RegistrationSettings: their defaults are
  // read from it (settings.hpp is the one source), so an untuned file changes nothing.
  Method method = Method::Ceres;
  double voxel_scale = 1.0;                                         // x each object's voxel (below)
  double feature_radius_vox = CoarseSettings{}.feature_radius_vox;  // FPFH radius, voxels
  int ransac_iterations = CoarseSettings{}.ransac_iterations;       // per attempt
  double max_correspondence_vox = RefineSettings{}.max_correspondence_vox;  // ICP gate, voxels
  double rho_icp_vox2 = RegistrationSettings{}.rho_icp_vox2;  // Algorithm 1: ICP fitness, vox^2
  double rho_rot_deg = RegistrationSettings{}.rho_rot_deg;    // Algorithm 1: gate around q0
  double max_rmse_vox = TrustSettings{}.max_rmse_vox;         // failure: inlier RMSE, voxels
  double min_overlap = TrustSettings{}.min_overlap;           // failure: fraction explained
  std::map<std::string, double> voxel_mm;  // per object name, mm (before voxel_scale)

  // Provenance.
  std::string benchmark, benchmark_file, benchmark_digest, train, test;
  uint64_t seed = 0;
  int held_out_registrations = 0, held_out_false_accepts = 0;
  double held_out_success_rate = 0, held_out_median_t_um = 0;

  // Settings for registering `object` (its voxel if listed, else `fallback_voxel_mm`).
  void apply(RegistrationSettings& s, const std::string& object,
             double fallback_voxel_mm = 0) const;
};

Thresholds load_thresholds(const std::string& path);
void write_thresholds(const std::string& path, const Thresholds& t);  // atomically
std::string thresholds_yaml(const Thresholds& t);

}  // namespace laserfit::registration
