#pragma once
// Helpers private to lib/sampling.
#include <cmath>
#include <sstream>

#include "laserfit/core/error.hpp"
#include "laserfit/sampling/sampling.hpp"

namespace laserfit::sampling {

constexpr size_t kBlock = 4096;             // points per RNG block (the unit of determinism)
constexpr uint64_t kStreamSurface = 0x5u;   // RNG stream id of surface sampling
constexpr size_t kMaxPoints = 200'000'000;  // beyond this a cloud no longer fits comfortably

// Exactly one of count / density, resolved to a point count over `area_mm2`.
inline size_t resolve_count(const SamplingSettings& s, double area_mm2) {
  if ((s.count > 0) == (s.density_per_mm2 > 0))
    throw Error("give either a point count or a density (points/mm^2), not both or neither");
  if (s.density_per_mm2 < 0 || !std::isfinite(s.density_per_mm2))
    throw Error("density must be a positive number of points per mm^2");
  const double n = s.count > 0 ? double(s.count) : std::round(s.density_per_mm2 * area_mm2);
  if (n < 1) throw Error("density too low: less than one point on the surface");
  if (n > double(kMaxPoints)) {
    std::ostringstream m;
    m << "would produce " << n << " points (limit " << kMaxPoints << ")";
    throw Error(m.str());
  }
  return static_cast<size_t>(n);
}

inline size_t candidate_count(size_t n, double oversampling) {
  if (!(oversampling >= 1.5)) throw Error("poisson oversampling must be at least 1.5");
  return static_cast<size_t>(std::ceil(n * oversampling));
}

inline PointCloud to_cloud(SurfaceSamples&& s, const char* method, const SamplingSettings& set) {
  PointCloud c;
  c.points = std::move(s.points);
  c.normals = std::move(s.normals);
  c.width = static_cast<int>(c.points.size());
  c.height = 1;
  c.metadata["method"] = method;
  c.metadata["seed"] = std::to_string(set.seed);
  return c;
}

}  // namespace laserfit::sampling
