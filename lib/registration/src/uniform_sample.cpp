// One real point per voxel straight from a scan's points, as pcl::UniformSampling chooses it and
// in its order, without first copying the scan into PCL's 48-byte points: for a 2.5 M-point
// organised scan the copy alone was a quarter of a second of every segmentation. The choice and
// the order are PCL's (test_registration compares them point for point): the voxel of p is
// floor(p / voxel) in float, its key the voxel's offset in the bounding grid (int arithmetic, as
// PCL's), the point kept the one nearest the voxel centre (PCL's 4-vector distance, w = 1 against
// 0), ties to the earlier point, voxels in the order of PCL's hash map of those keys.
#include <cmath>
#include <limits>
#include <unordered_map>

#include "pcl_types.hpp"

namespace laserfit::registration {
namespace {

// floor(v) as an int; out of range, INT_MIN: what PCL's static_cast gives on x86 (cvttss2si),
// here without undefined behaviour (a point 10^30 mm away in a hostile file).
int floor_int(float v) {
  const float f = std::floor(v);
  return f >= -2147483648.0f && f < 2147483648.0f ? int(f) : std::numeric_limits<int>::min();
}

}  // namespace

std::vector<size_t> uniform_sample(const std::vector<Eigen::Vector3f>& points, double voxel) {
  const float inv = 1.0f / static_cast<float>(voxel), size = static_cast<float>(voxel);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  for (const auto& p : points)
    if (p.allFinite()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const auto cell = [inv](const Eigen::Vector3f& p) {
    return Eigen::Vector3i(floor_int(p.x() * inv), floor_int(p.y() * inv), floor_int(p.z() * inv));
  };
  // Unsigned, then back to int: PCL's int arithmetic, which wraps on grids beyond 2^31 voxels.
  const auto offset = [](int a, int b) { return uint32_t(a) - uint32_t(b); };
  const Eigen::Vector3i min_b = cell(lo), max_b = cell(hi);
  const uint32_t mul_y = offset(max_b.x(), min_b.x()) + 1;
  const uint32_t mul_z = mul_y * (offset(max_b.y(), min_b.y()) + 1);
  struct Leaf {
    int idx = -1;
  };
  std::unordered_map<size_t, Leaf> leaves;  // PCL's map type: same keys, same iteration order
  // A profile's neighbours mostly share a voxel (12 um pitch, voxels of 30-300 um): the previous
  // point's leaf saves the hash lookup. Only new keys change the map, so its order is unchanged.
  size_t last_key = 0;
  Leaf* last = nullptr;  // nodes of an unordered_map stay where they are across rehashing
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    if (!p.allFinite()) continue;
    const Eigen::Vector3i ijk = cell(p);
    const size_t key = size_t(int(offset(ijk.x(), min_b.x()) + offset(ijk.y(), min_b.y()) * mul_y +
                                  offset(ijk.z(), min_b.z()) * mul_z));
    Leaf& leaf = last && key == last_key ? *last : leaves[key];
    last_key = key, last = &leaf;
    if (leaf.idx < 0) {
      leaf.idx = int(i);
      continue;
    }
    Eigen::Vector4f centre = (Eigen::Vector4f(float(ijk.x()), float(ijk.y()), float(ijk.z()), 0) +
                              Eigen::Vector4f::Constant(0.5f)) *
                             size;
    centre[3] = 0;
    const Eigen::Vector3f& q = points[size_t(leaf.idx)];
    const float cur = (Eigen::Vector4f(p.x(), p.y(), p.z(), 1) - centre).squaredNorm();
    const float prev = (Eigen::Vector4f(q.x(), q.y(), q.z(), 1) - centre).squaredNorm();
    if (cur < prev) leaf.idx = int(i);
  }
  std::vector<size_t> kept;
  kept.reserve(leaves.size());
  for (const auto& [key, leaf] : leaves) kept.push_back(size_t(leaf.idx));
  return kept;
}

PclCloud::Ptr to_pcl(const PointCloud& c, const std::vector<size_t>& at) {
  PclCloud::Ptr out(new PclCloud);
  out->resize(at.size());
  for (size_t k = 0; k < at.size(); ++k) {
    PointT& p = (*out)[k];
    p.getVector3fMap() = c.points[at[k]];
    p.getNormalVector3fMap() = c.has_normals() ? c.normals[at[k]] : Eigen::Vector3f::Zero();
    p.curvature = 0;
  }
  out->width = static_cast<uint32_t>(out->size());
  out->height = 1;
  out->is_dense = true;
  return out;
}

}  // namespace laserfit::registration
