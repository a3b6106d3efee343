// Segmentation of a scan into parts (needle vs thread tip, socket vs plug) by Euclidean
// clustering (PCL) on the downsampled scan: parts held apart by more than the cluster tolerance
// become separate clusters, largest first.
#include <pcl/segmentation/extract_clusters.h>

#include "laserfit/registration/preprocess.hpp"
#include "pcl_types.hpp"
#include "stages.hpp"

namespace laserfit::registration {

std::vector<PointCloud> segment_clusters(const PointCloud& scan, double voxel_mm,
                                         double tolerance_mm, size_t min_points) {
  PreprocessSettings pre;
  pre.outlier_std = 2.0;
  // Downsampled and filtered as for registration, without normals: clustering needs none.
  const PclCloud::Ptr cloud = sample_and_filter(scan, pre, voxel_mm);
  Tree::Ptr tree(new Tree);
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<PointT> ec;
  ec.setClusterTolerance(tolerance_mm);
  ec.setMinClusterSize(static_cast<int>(min_points));
  ec.setMaxClusterSize(static_cast<int>(cloud->size()));
  ec.setSearchMethod(tree);
  ec.setInputCloud(cloud);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);  // sorted by size, largest first
  // Each cluster is returned at full resolution: every scan point within one voxel of it, in
  // scan order. One pass over the scan for all clusters (their boxes may overlap).
  std::vector<Eigen::AlignedBox3f> boxes;
  for (const auto& idx : found) {
    Eigen::AlignedBox3f box;
    for (int i : idx.indices) box.extend(cloud->at(i).getVector3fMap());
    box.min().array() -= float(voxel_mm), box.max().array() += float(voxel_mm);
    boxes.push_back(box);
  }
  std::vector<PointCloud> out(boxes.size());
  const bool labels = !scan.labels.empty();
  for (size_t i = 0; i < scan.size(); ++i) {
    if (!scan.points[i].allFinite()) continue;
    for (size_t k = 0; k < boxes.size(); ++k)
      if (boxes[k].contains(scan.points[i])) {
        out[k].points.push_back(scan.points[i]);
        if (labels) out[k].labels.push_back(scan.labels[i]);
      }
  }
  for (auto& c : out) {
    c.width = static_cast<int>(c.points.size());
    c.metadata = scan.metadata, c.sensor_origin = scan.sensor_origin;
  }
  return out;
}

}  // namespace laserfit::registration
