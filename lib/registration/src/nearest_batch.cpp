// Batched nearest-neighbour queries on a Tree's input cloud with FLANN's single kd-tree (the index
// PCL builds, leaf size 15), queried once for all points instead of once per point.
#include <flann/flann.hpp>

#include "pcl_types.hpp"

namespace laserfit::registration {

struct Tree::Batch {
  std::vector<float> xyz;  // the finite input points, 3 floats each (FLANN keeps a pointer to it)
  std::vector<int> id;     // their indices in the input cloud
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> index;
};

void Tree::nearest_batch(const std::vector<Eigen::Vector3f>& queries, std::vector<int>& idx,
                         std::vector<float>& d2) const {
  // Built on first use (thread-safe): most trees only serve PCL's own searches.
  std::call_once(batch_once_, [this] {
    auto b = std::make_shared<Batch>();
    const auto& cloud = *getInputCloud();
    b->xyz.reserve(3 * cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i)
      if (cloud[i].getVector3fMap().allFinite())
        b->xyz.insert(b->xyz.end(), {cloud[i].x, cloud[i].y, cloud[i].z}), b->id.push_back(int(i));
    if (!b->id.empty()) {
      b->index = std::make_unique<flann::Index<flann::L2_Simple<float>>>(
          flann::Matrix<float>(b->xyz.data(), b->id.size(), 3), flann::KDTreeSingleIndexParams(15));
      b->index->buildIndex();
    }
    batch_ = std::move(b);
  });
  idx.assign(queries.size(), -1);
  d2.assign(queries.size(), std::numeric_limits<float>::infinity());
  if (!batch_->index || queries.empty()) return;
  std::vector<float> q;
  std::vector<size_t> at;  // finite queries only: FLANN asserts on NaN
  q.reserve(3 * queries.size());
  for (size_t i = 0; i < queries.size(); ++i)
    if (queries[i].allFinite()) q.insert(q.end(), {queries[i].x(), queries[i].y(), queries[i].z()}), at.push_back(i);
  if (at.empty()) return;
  std::vector<int> found(at.size());
  std::vector<float> dist(at.size());
  flann::Matrix<int> fi(found.data(), at.size(), 1);
  flann::Matrix<float> fd(dist.data(), at.size(), 1);
  flann::SearchParams sp(-1, 0.0f);  // exact search, as PCL's tree
  sp.cores = 1;                      // callers parallelise over registrations, not queries
  batch_->index->knnSearch(flann::Matrix<float>(q.data(), at.size(), 3), fi, fd, 1, sp);
  for (size_t k = 0; k < at.size(); ++k) idx[at[k]] = batch_->id[found[k]], d2[at[k]] = dist[k];
}

}  // namespace laserfit::registration
