#pragma once
// PCL types and conversions (private to lib/registration; only its .cpp files include PCL).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/pose.hpp"

namespace laserfit::registration {

using PointT = pcl::PointNormal;
using PclCloud = pcl::PointCloud<PointT>;
// PCL's kd-tree library is built with assertions: a non-finite query (a PCL ICP whose estimate
// went NaN on degenerate data) aborts the process. This tree answers such a query with one
// infinitely distant neighbour instead (no neighbour within a radius), which every correspondence
// gate then rejects.
// PCL asks FLANN one query at a time through flann::Index, which opens an OpenMP region per call
// (even for one thread): on this 2-core VM that was half the time of a registration of a 1 M-point
// scan (segmentation's clustering and normals, FPFH). So the single-point searches go straight to
// the same FLANN kd-tree (KDTreeSingleIndex, leaf size 15, built on the same finite points in the
// same order) with the same result sets: the same neighbours in the same order as PCL's path.
class Tree : public pcl::search::KdTree<PointT> {
 public:
  using Ptr = std::shared_ptr<Tree>;
  using pcl::search::KdTree<PointT>::nearestKSearch;
  using pcl::search::KdTree<PointT>::radiusSearch;
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override;
  int nearestKSearch(const PointT& p, int k, pcl::Indices& idx,
                     std::vector<float>& d2) const override;
  int radiusSearch(const PointT& p, double radius, pcl::Indices& idx, std::vector<float>& d2,
                   unsigned int max_nn = 0) const override;
  // Nearest input point of every query (finite queries only), in one call; with max_d2, only
  // those at a squared distance of at most max_d2 (mm^2). idx[i] = -1 when none.
  void nearest_batch(const std::vector<Eigen::Vector3f>& queries, std::vector<int>& idx,
                     std::vector<float>& d2,
                     float max_d2 = std::numeric_limits<float>::infinity()) const;

 private:
  struct Direct;
  const Direct* direct() const;  // built on first use (thread-safe); null when indices were given
  mutable std::shared_ptr<Direct> direct_;
  mutable std::unique_ptr<std::once_flag> once_ = std::make_unique<std::once_flag>();
};

// near[i] = 1 when queries[i] has a point of `points` strictly within `radius` (mm); non-finite
// queries are never near. On a uniform grid (within_radius.cpp); the kd-tree version (one bounded
// FLANN search over all queries, nearest_batch.cpp) answers where the grid would be too large.
std::vector<char> within_radius(const std::vector<Eigen::Vector3f>& points,
                                const std::vector<Eigen::Vector3f>& queries, double radius);
std::vector<char> within_radius_kdtree(const std::vector<Eigen::Vector3f>& points,
                                       const std::vector<Eigen::Vector3f>& queries, double radius);

// Finite points only (NaN = no measurement); normals copied when present.
PclCloud::Ptr to_pcl(const PointCloud& c);
// The points at `at`, in that order; normals copied when present.
PclCloud::Ptr to_pcl(const PointCloud& c, const std::vector<size_t>& at);
// The indices of the finite points pcl::UniformSampling keeps at `voxel` (mm), in its output
// order (uniform_sample.cpp).
std::vector<size_t> uniform_sample(const std::vector<Eigen::Vector3f>& points, double voxel);

inline Eigen::Matrix4f to_matrix4f(const Pose& T) { return T.matrix().cast<float>(); }
inline Pose from_matrix4f(const Eigen::Matrix4f& M) {
  Pose T = Pose::Identity();
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>().cast<double>();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();  // re-orthonormalise
  T.translation() = M.topRightCorner<3, 1>().cast<double>();
  return T;
}

}  // namespace laserfit::registration
