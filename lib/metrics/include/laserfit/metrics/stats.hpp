#pragma once
// Summary statistics of measured samples.
#include <vector>

namespace laserfit::metrics {

// q-quantile (0..1) by linear interpolation between order statistics; NaN for no samples.
double quantile(std::vector<double> v, double q);
inline double median(const std::vector<double>& v) { return quantile(v, 0.5); }

}  // namespace laserfit::metrics
