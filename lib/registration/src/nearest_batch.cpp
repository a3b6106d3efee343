// Tree's searches straight on FLANN's single kd-tree (the index PCL builds, leaf size 15), without
// flann::Index's OpenMP region per call; batched nearest-neighbour and within-radius queries.
#include <flann/flann.hpp>

#include <cmath>

#include "pcl_types.hpp"

namespace laserfit::registration {

namespace {

// The finite points among point(0) .. point(n - 1) as FLANN's rows (3 floats each) and where
// each came from: FLANN asserts on NaN.
template <class Point>
size_t finite_rows(size_t n, Point point, std::vector<float>& xyz, std::vector<size_t>& at) {
  xyz.clear(), at.clear();
  xyz.reserve(3 * n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f p = point(i);
    if (p.allFinite()) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()}), at.push_back(i);
  }
  return at.size();
}

size_t finite_rows(const std::vector<Eigen::Vector3f>& pts, std::vector<float>& xyz,
                   std::vector<size_t>& at) {
  return finite_rows(
      pts.size(), [&](size_t i) { return pts[i]; }, xyz, at);
}

}  // namespace

struct Tree::Direct {
  std::vector<float> xyz;  // the finite input points, 3 floats each (FLANN keeps a pointer to it)
  std::vector<size_t> id;  // their indices in the input cloud
  std::unique_ptr<flann::KDTreeSingleIndex<flann::L2_Simple<float>>> index;
};

void Tree::setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices) {
  pcl::search::KdTree<PointT>::setInputCloud(cloud, indices);
  direct_.reset();
  once_ = std::make_unique<std::once_flag>();  // searches never run concurrently with this
}

const Tree::Direct* Tree::direct() const {
  std::call_once(*once_, [this] {
    const auto& in = getIndices();
    if (in && !in->empty()) return;  // a subset: PCL's own path maps it
    auto b = std::make_shared<Direct>();
    const auto& cloud = *getInputCloud();
    if (finite_rows(
            cloud.size(), [&](size_t i) { return cloud[i].getVector3fMap(); }, b->xyz, b->id)) {
      b->index = std::make_unique<flann::KDTreeSingleIndex<flann::L2_Simple<float>>>(
          flann::Matrix<float>(b->xyz.data(), b->id.size(), 3), flann::KDTreeSingleIndexParams(15));
      b->index->buildIndex();
    }
    direct_ = std::move(b);
  });
  return direct_.get();
}

int Tree::nearestKSearch(const PointT& p, int k, pcl::Indices& idx, std::vector<float>& d2) const {
  if (!p.getVector3fMap().allFinite()) {
    idx.assign(1, 0);
    d2.assign(1, std::numeric_limits<float>::infinity());
    return 1;
  }
  const Direct* b = direct();
  if (!b || !b->index || k <= 0) return pcl::search::KdTree<PointT>::nearestKSearch(p, k, idx, d2);
  // As KdTreeFLANN::nearestKSearch and NNIndex::knnSearch: k capped at the size, sorted, the heap
  // result set above FLANN's threshold.
  const size_t kk = std::min(size_t(k), b->id.size());
  flann::SearchParams sp(-1, getEpsilon());
  std::vector<size_t> found(kk);
  d2.resize(kk);
  const float q[3] = {p.x, p.y, p.z};
  size_t n = 0;
  if (kk > size_t(KNN_HEAP_THRESHOLD)) {  // FLANN's macro (nn_index.h)
    flann::KNNResultSet2<float> rs(kk);
    b->index->findNeighbors(rs, q, sp);
    n = std::min(rs.size(), kk);
    rs.copy(found.data(), d2.data(), n, sp.sorted);
  } else {
    flann::KNNSimpleResultSet<float> rs(kk);
    b->index->findNeighbors(rs, q, sp);
    n = std::min(rs.size(), kk);
    rs.copy(found.data(), d2.data(), n, sp.sorted);
  }
  idx.resize(kk);
  for (size_t i = 0; i < n; ++i) idx[i] = int(b->id[found[i]]);
  return int(kk);
}

int Tree::radiusSearch(const PointT& p, double radius, pcl::Indices& idx, std::vector<float>& d2,
                       unsigned int max_nn) const {
  if (!p.getVector3fMap().allFinite()) {
    idx.clear(), d2.clear();
    return 0;
  }
  const Direct* b = direct();
  if (!b || !b->index) return pcl::search::KdTree<PointT>::radiusSearch(p, radius, idx, d2, max_nn);
  // As KdTreeFLANN::radiusSearch and NNIndex::radiusSearch: all neighbours unless max_nn is below
  // the size, squared radius in float, sorted as the tree was asked to.
  const size_t total = b->id.size();
  flann::SearchParams sp(-1, getEpsilon(), sorted_results_);
  const float r2 = static_cast<float>(radius * radius);
  const float q[3] = {p.x, p.y, p.z};
  std::vector<size_t> found;
  size_t n = 0;
  if (max_nn == 0 || max_nn >= total) {
    flann::RadiusResultSet<float> rs(r2);
    b->index->findNeighbors(rs, q, sp);
    n = rs.size();
    found.resize(n), d2.resize(n);
    if (n > 0) rs.copy(found.data(), d2.data(), n, sp.sorted);
  } else {
    flann::KNNRadiusResultSet<float> rs(r2, max_nn);
    b->index->findNeighbors(rs, q, sp);
    n = std::min(rs.size(), size_t(max_nn));
    found.resize(n), d2.resize(n);
    if (n > 0) rs.copy(found.data(), d2.data(), n, sp.sorted);
  }
  idx.resize(n);
  for (size_t i = 0; i < n; ++i) idx[i] = int(b->id[found[i]]);
  return int(n);
}

void Tree::nearest_batch(const std::vector<Eigen::Vector3f>& queries, std::vector<int>& idx,
                         std::vector<float>& d2, float max_d2) const {
  idx.assign(queries.size(), -1);
  d2.assign(queries.size(), std::numeric_limits<float>::infinity());
  const Direct* b = direct();
  if (!b || !b->index || queries.empty()) return;
  std::vector<float> q;
  std::vector<size_t> at;
  if (finite_rows(queries, q, at) == 0) return;
  std::vector<size_t> found(at.size());
  std::vector<float> dist(at.size());
  flann::Matrix<size_t> fi(found.data(), at.size(), 1);
  flann::Matrix<float> fd(dist.data(), at.size(), 1);
  flann::SearchParams sp(-1, 0.0f);  // exact search, as PCL's tree
  sp.cores = 1;                      // callers parallelise over registrations, not queries
  const flann::Matrix<float> qm(q.data(), at.size(), 3);
  if (std::isinf(max_d2)) {
    b->index->knnSearch(qm, fi, fd, 1, sp);
  } else {
    // Bounded: a query far from every point is pruned at the bound instead of searched down to
    // its nearest point. The same tree walked in the same order, with the same strict test
    // against the best so far, gives the nearest point within the bound that knnSearch gives.
    // FLANN's bound is strict: the next float up keeps a point at exactly max_d2.
    sp.max_neighbors = 1;
    b->index->radiusSearch(qm, fi, fd, std::nextafter(max_d2, HUGE_VALF), sp);
  }
  for (size_t k = 0; k < at.size(); ++k)
    if (dist[k] <= max_d2) idx[at[k]] = int(b->id[found[k]]), d2[at[k]] = dist[k];
}

std::vector<char> within_radius_kdtree(const std::vector<Eigen::Vector3f>& points,
                                       const std::vector<Eigen::Vector3f>& queries, double radius) {
  std::vector<char> near(queries.size(), 0);
  std::vector<float> xyz, q;
  std::vector<size_t> from, at;
  if (finite_rows(points, xyz, from) == 0 || finite_rows(queries, q, at) == 0 || !(radius > 0))
    return near;
  flann::KDTreeSingleIndex<flann::L2_Simple<float>> index(
      flann::Matrix<float>(xyz.data(), xyz.size() / 3, 3), flann::KDTreeSingleIndexParams(15));
  index.buildIndex();
  std::vector<size_t> found(at.size());
  std::vector<float> dist(at.size());
  flann::Matrix<size_t> fi(found.data(), at.size(), 1);
  flann::Matrix<float> fd(dist.data(), at.size(), 1);
  // At most one neighbour inside the radius: far queries are pruned at the radius, not searched
  // down to their nearest point (most scan points are far from the part). FLANN's L2 is squared.
  flann::SearchParams sp(-1, 0.0f);
  sp.max_neighbors = 1, sp.cores = 1;
  const float r2 = float(radius * radius);
  index.radiusSearch(flann::Matrix<float>(q.data(), at.size(), 3), fi, fd, r2, sp);
  for (size_t k = 0; k < at.size(); ++k) near[at[k]] = dist[k] <= r2;
  return near;
}

}  // namespace laserfit::registration
