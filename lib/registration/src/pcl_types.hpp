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
// infinitely distant neighbour instead, which every correspondence gate then rejects.
class Tree : public pcl::search::KdTree<PointT> {
 public:
  using Ptr = std::shared_ptr<Tree>;
  using pcl::search::KdTree<PointT>::nearestKSearch;
  int nearestKSearch(const PointT& p, int k, pcl::Indices& idx, std::vector<float>& d2) const override {
    if (!p.getVector3fMap().allFinite()) {
      idx.assign(1, 0);
      d2.assign(1, std::numeric_limits<float>::infinity());
      return 1;
    }
    return pcl::search::KdTree<PointT>::nearestKSearch(p, k, idx, d2);
  }
  // Nearest input point of every query (finite queries only), in one call: PCL asks FLANN one
  // query at a time, and FLANN opens an OpenMP region per call; at ~10^6 queries per
  // registration that overhead was most of its run time. idx[i] = -1 when none. Built on first
  // use for the cloud set then: a Tree is given one input cloud in its life (as everywhere here).
  void nearest_batch(const std::vector<Eigen::Vector3f>& queries, std::vector<int>& idx,
                     std::vector<float>& d2) const;

 private:
  struct Batch;
  mutable std::shared_ptr<Batch> batch_;
  mutable std::once_flag batch_once_;
};

// Finite points only (NaN = no measurement); normals copied when present.
PclCloud::Ptr to_pcl(const PointCloud& c);

inline Eigen::Matrix4f to_matrix4f(const Pose& T) { return T.matrix().cast<float>(); }
inline Pose from_matrix4f(const Eigen::Matrix4f& M) {
  Pose T = Pose::Identity();
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>().cast<double>();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();  // re-orthonormalise
  T.translation() = M.topRightCorner<3, 1>().cast<double>();
  return T;
}

}  // namespace laserfit::registration
