#include "laserfit/scan/settings.hpp"

#include <cmath>

#include "laserfit/core/error.hpp"

namespace laserfit::scan {

int SweepSettings::profiles() const {
  return static_cast<int>(std::floor(length_mm / spacing_mm() + 1e-9)) + 1;
}

void ScanSettings::validate(const std::string& what) const {
  auto bad = [&](const std::string& m) { throw Error(what, m); };
  sensor.validate(what);
  if (!(sweep.speed_mm_s > 0) || !std::isfinite(sweep.speed_mm_s))
    bad("sweep: speed_mm_s must be positive");
  if (!(sweep.profile_rate_hz > 0) || sweep.profile_rate_hz > 100000)
    bad("sweep: profile_rate_hz must be in (0, 100000]");
  if (!(sweep.length_mm >= 0) || !std::isfinite(sweep.length_mm))
    bad("sweep: length_mm must be >= 0");
  if (std::abs(sweep.direction.norm() - 1.0) > 1e-6) bad("sweep: direction must be a unit vector");
  if (sweep.length_mm / sweep.spacing_mm() > 200000) bad("sweep: more than 200000 profiles");
  const auto& n = noise;
  for (double v : {n.depth_sigma_um, n.x_jitter_um, n.z_quantum_um, n.speckle_sigma_um,
                   n.speckle_corr_um, n.dropout_rate, n.mixed_pixel_prob, n.mixed_pixel_jump_mm,
                   n.outlier_rate, n.outlier_max_mm, n.bias_sigma_um})
    if (!(v >= 0) || !std::isfinite(v)) bad("noise: values must be finite and >= 0");
  if (n.dropout_rate > 1 || n.mixed_pixel_prob > 1 || n.outlier_rate > 1)
    bad("noise: probabilities must be <= 1");
  if (!(n.grazing_start_deg >= 0 && n.grazing_start_deg < sensor.max_incidence_deg))
    bad("noise: grazing_start_deg must be in [0, max_incidence_deg)");
  const auto& m = motion;
  for (double v : {m.offset_sigma_mm, m.offset_sigma_deg, m.jitter_sigma_mm, m.jitter_sigma_deg})
    if (!(v >= 0) || !std::isfinite(v)) bad("motion: sigmas must be finite and >= 0");
  if (!(m.jitter_corr_profiles >= 1)) bad("motion: jitter_corr_profiles must be >= 1");
  for (double v : m.calibration_error)
    if (!std::isfinite(v)) bad("motion: calibration_error must be finite");
}

}  // namespace laserfit::scan
