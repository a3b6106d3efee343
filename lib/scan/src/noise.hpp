#pragma once
// Sensor noise and artefacts on one profile (private to lib/scan).
#include <vector>
#include "laserfit/core/rng.hpp"

#include "laserfit/scan/scanner.hpp"

namespace laserfit::scan {

// One column of a profile before noise: the true measurement in the (true) sensor frame.
struct Sample {
  bool valid = false;
  double x = 0, z = 0;    // mm, sensor frame (laser plane y = 0)
  double ux = 0, uz = 1;  // unit direction of the laser ray (sensor frame)
  double cos_incidence = 1;
  bool shiny = false;
};

// Applies, in this order: mixed pixels at depth jumps (on the true depths), dropouts (low
// signal, grazing angles), depth noise along the laser ray (sigma / cos incidence) plus speckle
// correlated along the profile, x jitter, specular outliers, per-scan bias, depth quantisation.
void apply_noise(std::vector<Sample>& profile, const NoiseSettings& n,
                 const sensor::LineScannerGeometry& g, double bias_mm, Mt19937_64& rng,
                 ScanStats& stats);

}  // namespace laserfit::scan
