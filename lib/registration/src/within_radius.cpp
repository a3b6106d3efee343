// within_radius on a uniform grid: a crop keeps the scan points near the placed reference, up to
// millions of queries against up to a million points (the reference swept along a plateau). A
// kd-tree search per query was a third of a benchmark's time; a grid of cells r / sqrt(3) wide
// answers most queries from their own cell (any point there is within r) and the rest from the
// 5 x 5 x 5 cells around it. Exact: every answer is a distance test, computed as FLANN's L2 does
// (float, dimension by dimension) and strict (d < r^2) as FLANN's result sets are.
#include <cmath>

#include "pcl_types.hpp"

namespace laserfit::registration {
namespace {

// The points bucketed by cell (counting sort): the points of cell c are at[start[c] .. start[c+1]).
struct Grid {
  Eigen::Vector3f origin;
  float inv_cell = 0;
  Eigen::Array3i dims;
  std::vector<uint32_t> start;
  std::vector<Eigen::Vector3f> at;
  bool cell_of(const Eigen::Vector3f& p, Eigen::Array3i& c) const {
    const Eigen::Array3f f = ((p - origin) * inv_cell).array().floor();
    if ((f < 0).any() || (f >= dims.cast<float>()).any()) return false;
    c = f.cast<int>();
    return true;
  }
  size_t index(const Eigen::Array3i& c) const {
    return (size_t(c.z()) * size_t(dims.y()) + size_t(c.y())) * size_t(dims.x()) + size_t(c.x());
  }
};

constexpr size_t kMaxCells = size_t(1) << 24;  // 64 MiB of cell starts; beyond, the kd-tree

bool build(const std::vector<Eigen::Vector3f>& points, float radius, Grid& g) {
  Eigen::AlignedBox3f box;
  for (const auto& p : points)
    if (p.allFinite()) box.extend(p);
  if (box.isEmpty()) return false;
  const float cell = radius / std::sqrt(3.0f) * 0.999f;
  g.inv_cell = 1.0f / cell;
  g.origin = box.min() - Eigen::Vector3f::Constant(2 * cell);
  const Eigen::Array3f extent = (box.max() - g.origin).array() * g.inv_cell + 3;
  if ((extent > 4e6f).any() || extent.prod() > float(kMaxCells)) return false;
  g.dims = extent.ceil().cast<int>();
  g.start.assign(size_t(g.dims.prod()) + 1, 0);
  std::vector<uint32_t> cell_of(points.size(), UINT32_MAX);
  Eigen::Array3i c;
  for (size_t i = 0; i < points.size(); ++i)
    if (points[i].allFinite() && g.cell_of(points[i], c)) ++g.start[(cell_of[i] = g.index(c)) + 1];
  for (size_t k = 1; k < g.start.size(); ++k) g.start[k] += g.start[k - 1];
  g.at.resize(g.start.back());
  std::vector<uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (size_t i = 0; i < points.size(); ++i)
    if (cell_of[i] != UINT32_MAX) g.at[fill[cell_of[i]]++] = points[i];
  return true;
}

bool any_within(const Grid& g, const Eigen::Vector3f& q, const Eigen::Array3i& c, float r2) {
  auto test = [&](size_t cell) {
    for (uint32_t k = g.start[cell]; k < g.start[cell + 1]; ++k) {
      const Eigen::Vector3f& p = g.at[k];
      float d = 0;
      for (int j = 0; j < 3; ++j) {
        const float diff = q[j] - p[j];
        d += diff * diff;
      }
      if (d < r2) return true;
    }
    return false;
  };
  if (test(g.index(c))) return true;  // the usual answer for a query on the part
  for (int dz = -2; dz <= 2; ++dz)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const Eigen::Array3i n = c + Eigen::Array3i(dx, dy, dz);
        if ((n < 0).any() || (n >= g.dims).any() || (!dx && !dy && !dz)) continue;
        if (test(g.index(n))) return true;
      }
  return false;
}

}  // namespace

std::vector<char> within_radius(const std::vector<Eigen::Vector3f>& points,
                                const std::vector<Eigen::Vector3f>& queries, double radius) {
  std::vector<char> near(queries.size(), 0);
  if (!(radius > 0) || !std::isfinite(radius)) return near;
  Grid g;
  if (!build(points, float(radius), g)) return within_radius_kdtree(points, queries, radius);
  const float r2 = float(radius * radius);
  Eigen::Array3i c;
  for (size_t i = 0; i < queries.size(); ++i)
    near[i] =
        queries[i].allFinite() && g.cell_of(queries[i], c) && any_within(g, queries[i], c, r2);
  return near;
}

}  // namespace laserfit::registration
