// Segmentation of a scan into parts (needle vs thread tip, socket vs plug) by Euclidean
// clustering (PCL) on the downsampled scan: parts held apart by more than the cluster tolerance
// become separate clusters, largest first.
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>

#include "laserfit/registration/preprocess.hpp"
#include "pcl_types.hpp"
#include "stages.hpp"

namespace laserfit::registration {

std::vector<pcl::PointIndices> euclidean_clusters(const PclCloud::Ptr& cloud, double tolerance_mm,
                                                  size_t min_points) {
  // pcl::EuclideanClusterExtraction::extract without its index list, which would send every
  // search through FLANN's OpenMP region per query (three quarters of the clustering's time):
  // the same searches on the same tree, the same clusters in the same order. Unsorted
  // neighbours: a cluster is the connected component of its seed (the sorted search only skips
  // the query itself, found first), and no two sampled points coincide (one per voxel).
  std::vector<pcl::PointIndices> found;
  if (cloud->empty()) return found;
  Tree::Ptr tree(new Tree);
  tree->setSortedResults(false);
  tree->setInputCloud(cloud);
  pcl::extractEuclideanClusters(*cloud, tree, float(tolerance_mm), found,
                                static_cast<unsigned>(min_points), unsigned(cloud->size()));
  std::sort(found.rbegin(), found.rend(), pcl::comparePointClusters);  // largest first
  return found;
}

std::vector<PointCloud> segment_clusters(const PointCloud& scan, double voxel_mm,
                                         double tolerance_mm, size_t min_points) {
  PreprocessSettings pre;
  pre.outlier_std = 2.0;
  // Downsampled and filtered as for registration, without normals: clustering needs none.
  const PclCloud::Ptr cloud = sample_and_filter(scan, pre, voxel_mm);
  const std::vector<pcl::PointIndices> found = euclidean_clusters(cloud, tolerance_mm, min_points);
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
