#include "noise.hpp"

#include <cmath>

#include "laserfit/core/rng.hpp"

namespace laserfit::scan {
namespace {

constexpr double kUm = 1e-3;  // micrometres -> mm

// Moves a sample by `d` mm along its own laser ray (triangulation errors lie along the ray).
void along_ray(Sample& s, double d) {
  s.x += d * s.ux;
  s.z += d * s.uz;
}

}  // namespace

void apply_noise(std::vector<Sample>& p, const NoiseSettings& n,
                 const sensor::LineScannerGeometry& g, double bias_mm, Mt19937_64& rng,
                 ScanStats& stats) {
  const size_t m = p.size();
  // Mixed pixels: the spot straddles a depth edge and the peak lands in between.
  if (n.mixed_pixel_prob > 0)
    for (size_t j = 0; j + 1 < m; ++j) {
      Sample &a = p[j], &b = p[j + 1];
      if (!a.valid || !b.valid || std::abs(a.z - b.z) <= n.mixed_pixel_jump_mm) continue;
      if (uniform01(rng) >= n.mixed_pixel_prob) continue;
      Sample& far = a.z > b.z ? a : b;
      const Sample& near = a.z > b.z ? b : a;
      along_ray(far, -uniform01(rng) * (far.z - near.z));
      ++stats.mixed_pixels;
      ++j;  // do not chain through the sample just moved
    }
  // Speckle: AR(1) along the profile with the configured correlation length. Drawn only where
  // there is a measurement; across a gap of k columns the exact AR(1) step is rho^k.
  NormalSource normal(rng);
  const double rho =
      n.speckle_corr_um > 0 ? std::exp(-g.pitch_mid_mm() / (n.speckle_corr_um * kUm)) : 0.0;
  const double s_sp = n.speckle_sigma_um * kUm;
  double speckle = 0.0, decay = 0.0;  // decay = rho^(columns since the last draw); 0: fresh start
  const double cos_graze = std::cos(n.grazing_start_deg * M_PI / 180.0);
  const double cos_max = std::cos(g.max_incidence_deg * M_PI / 180.0);
  for (size_t j = 0; j < m; ++j, decay *= rho) {
    Sample& s = p[j];
    if (!s.valid) continue;
    speckle = decay * speckle + std::sqrt(1 - decay * decay) * normal() * s_sp;
    decay = 1.0;
    // Dropouts: a base rate plus a ramp to certainty between grazing_start and max incidence.
    double p_drop = n.dropout_rate;
    if (s.cos_incidence < cos_graze)
      p_drop += (cos_graze - s.cos_incidence) / (cos_graze - cos_max);
    if (uniform01(rng) < p_drop) {
      s.valid = false;
      ++stats.dropouts;
      continue;
    }
    const double sigma = n.depth_sigma_um * kUm / std::max(s.cos_incidence, 0.05);
    along_ray(s, normal() * sigma + speckle);
    s.x += normal() * n.x_jitter_um * kUm;
    if (s.shiny && uniform01(rng) < n.outlier_rate) {
      along_ray(s, (2 * uniform01(rng) - 1) * n.outlier_max_mm);
      ++stats.outliers;
    }
    s.z += bias_mm;
    if (n.z_quantum_um > 0) s.z = std::round(s.z / (n.z_quantum_um * kUm)) * (n.z_quantum_um * kUm);
  }
}

}  // namespace laserfit::scan
