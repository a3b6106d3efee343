#include "laserfit/registration/preprocess.hpp"
#include "laserfit/core/cpu_budget.hpp"

#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/voxel_grid.h>

#include <algorithm>
#include <limits>

#include "laserfit/core/error.hpp"
#include "pcl_types.hpp"
#include "stages.hpp"

namespace laserfit::registration {

PclCloud::Ptr to_pcl(const PointCloud& c) {
  std::vector<size_t> finite;
  finite.reserve(c.size());
  for (size_t i = 0; i < c.size(); ++i)
    if (c.points[i].allFinite()) finite.push_back(i);
  return to_pcl(c, finite);
}

double auto_voxel_mm(const PointCloud& ref) {
  Eigen::AlignedBox3f box;
  for (const auto& p : ref.points)
    if (p.allFinite()) box.extend(p);
  if (box.isEmpty()) throw Error("reference cloud has no finite points");
  return box.diagonal().norm() / 150.0;
}

PclCloud::Ptr with_normals(const PclCloud::Ptr& cloud, const PclCloud::Ptr& surface, double radius,
                           const PreprocessSettings& s, bool keep_side) {
  pcl::NormalEstimationOMP<PointT, PointT> ne(threads_or(2));  // same normals for any count
  ne.setInputCloud(cloud);
  ne.setSearchSurface(surface);
  ne.setSearchMethod(Tree::Ptr(new Tree));
  ne.setRadiusSearch(radius);
  PclCloud est;
  ne.compute(est);
  PclCloud::Ptr out(new PclCloud);
  out->reserve(cloud->size());
  for (size_t i = 0; i < est.size(); ++i) {
    PointT p = (*cloud)[i];
    Eigen::Vector3f n = est[i].getNormalVector3fMap();
    if (!n.allFinite()) continue;  // isolated point: no normal
    if (s.use_viewpoint) {
      if (n.dot(s.viewpoint.cast<float>() - p.getVector3fMap()) < 0) n = -n;
    } else if (keep_side && p.getNormalVector3fMap().dot(n) < 0) {
      n = -n;  // keep the CAD's outward side
    }
    p.getNormalVector3fMap() = n;
    p.curvature = est[i].curvature;
    out->push_back(p);
  }
  out->width = static_cast<uint32_t>(out->size());
  out->height = 1;
  return out;
}

namespace {

// pcl::StatisticalOutlierRemoval (PCL 1.13, negative off) searching through Tree (pcl_types.hpp):
// the same FLANN tree, neighbours and arithmetic (float squares, double sums: as PCL's build
// computes them), without an OpenMP region per query, which was half of the filter's time. A
// point is an outlier when its mean distance to its k nearest neighbours is above the mean of
// those distances plus std_mul standard deviations. `in` is finite (to_pcl).
PclCloud::Ptr remove_outliers(const PclCloud::Ptr& in, int k, double std_mul) {
  Tree tree;
  tree.setInputCloud(in);
  std::vector<float> mean_d(in->size());
  pcl::Indices idx;
  std::vector<float> d2;
  for (size_t i = 0; i < in->size(); ++i) {
    if (tree.nearestKSearch((*in)[i], k + 1, idx, d2) == 0) continue;  // not for k >= 1
    double sum = 0.0;
    for (int j = 1; j <= k; ++j) sum += std::sqrt(double(d2[j]));  // j = 0: the point itself
    mean_d[i] = static_cast<float>(sum / k);
  }
  double sum = 0, sq_sum = 0;
  for (const float d : mean_d) sum += d, sq_sum += d * d;
  const double n = double(mean_d.size());
  const double mean = sum / n, variance = (sq_sum - sum * sum / n) / (n - 1);
  const double limit = mean + std_mul * std::sqrt(variance);
  PclCloud::Ptr out(new PclCloud);
  out->reserve(in->size());
  for (size_t i = 0; i < in->size(); ++i)
    if (!(mean_d[i] > limit)) out->push_back((*in)[i]);
  out->width = static_cast<uint32_t>(out->size()), out->height = 1;
  return out;
}

}  // namespace

PclCloud::Ptr sample_and_filter(const PointCloud& c, const PreprocessSettings& s, double voxel) {
  // The input point nearest each voxel centre (pcl::UniformSampling's choice and order).
  PclCloud::Ptr d = to_pcl(c, uniform_sample(c.points, voxel));
  if (s.outlier_std > 0 && s.outlier_neighbours > 0 && d->size() > size_t(s.outlier_neighbours))
    d = remove_outliers(d, s.outlier_neighbours, s.outlier_std);
  return d;
}

PclCloud::Ptr coarser(const PclCloud::Ptr& fine, double cvox, const PreprocessSettings& s,
                      bool keep_side) {
  // Features need a regular density, not unbiased points: the voxel grid's centroids will do.
  pcl::VoxelGrid<PointT> vg;
  vg.setInputCloud(fine);
  vg.setLeafSize(float(cvox), float(cvox), float(cvox));
  PclCloud::Ptr d(new PclCloud);
  vg.filter(*d);  // averages the normals too: their side is kept for keep_side
  return with_normals(d, fine, s.normal_radius_vox * cvox, s, keep_side);
}

size_t remove_mixed_pixels(PointCloud& c, double factor) {
  const size_t W = size_t(std::max(c.width, 0)), H = size_t(std::max(c.height, 0));
  if (H < 2 || W < 3 || W * H != c.points.size()) return 0;
  auto gap = [&](size_t i, size_t j) {
    const auto &a = c.points[i], &b = c.points[j];
    return a.allFinite() && b.allFinite() ? (a - b).norm() : std::numeric_limits<float>::infinity();
  };
  std::vector<float> d;  // in-profile spacing, sampled
  for (size_t i = 0; i + 1 < c.points.size(); i += 7)
    if ((i + 1) % W != 0 && std::isfinite(gap(i, i + 1))) d.push_back(gap(i, i + 1));
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  const float limit = float(factor) * d[d.size() / 2];
  std::vector<size_t> drop;
  for (size_t r = 0; r < H; ++r)
    for (size_t x = 0; x < W; ++x) {
      const size_t i = r * W + x;
      if (!c.points[i].allFinite()) continue;
      const float l = x > 0 ? gap(i, i - 1) : std::numeric_limits<float>::infinity();
      const float rr = x + 1 < W ? gap(i, i + 1) : std::numeric_limits<float>::infinity();
      if (std::min(l, rr) > limit) drop.push_back(i);
    }
  for (size_t i : drop)
    c.points[i] = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  return drop.size();
}

PclCloud::Ptr prepare(const PointCloud& in, const PreprocessSettings& s, double voxel) {
  // Empty only without a finite point: the outlier filter never removes every point.
  const PclCloud::Ptr d = sample_and_filter(in, s, voxel);
  if (d->empty()) throw Error("cloud has no finite points");
  if (d->size() < 10) throw Error("fewer than 10 points left after filtering and downsampling");
  const PclCloud::Ptr n = with_normals(d, d, s.normal_radius_vox * voxel, s, in.has_normals());
  if (n->size() < 10) throw Error("fewer than 10 points with normals after preprocessing");
  return n;
}

PointCloud preprocess(const PointCloud& in, const PreprocessSettings& s, double voxel) {
  const PclCloud::Ptr n = prepare(in, s, voxel);
  PointCloud out;
  for (const auto& p : *n) {
    out.points.push_back(p.getVector3fMap());
    out.normals.push_back(p.getNormalVector3fMap());
  }
  out.width = static_cast<int>(out.points.size());
  out.height = 1;
  return out;
}

}  // namespace laserfit::registration
