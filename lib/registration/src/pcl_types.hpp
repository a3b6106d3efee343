#pragma once
// PCL types and conversions (private to lib/registration; only its .cpp files include PCL).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/pose.hpp"

namespace laserfit::registration {

using PointT = pcl::PointNormal;
using PclCloud = pcl::PointCloud<PointT>;
using Tree = pcl::search::KdTree<PointT>;

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
