// The registration's kd-tree (lib/registration/src/pcl_types.hpp) answers PCL's single-point
// searches on FLANN directly; these must equal PCL's own KdTree exactly (same indices in the same
// order, bit-equal squared distances), or every registration would change with the speed-up.
#include <gtest/gtest.h>

#include <random>

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/uniform_sampling.h>
#include <pcl/segmentation/extract_clusters.h>

#include "pcl_types.hpp"
#include "stages.hpp"

using namespace laserfit::registration;

namespace {

PclCloud::Ptr random_cloud(size_t n, uint32_t seed, bool with_nan) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  PclCloud::Ptr c(new PclCloud);
  for (size_t i = 0; i < n; ++i) {
    PointT p;
    p.x = u(rng), p.y = u(rng), p.z = 0.2f * u(rng);  // a slab: many equal-ish distances
    if (with_nan && i % 97 == 5) p.x = std::numeric_limits<float>::quiet_NaN();
    c->push_back(p);
  }
  c->is_dense = !with_nan;
  return c;
}

struct Both {
  Tree direct;
  pcl::search::KdTree<PointT> pcl_tree;
  explicit Both(const PclCloud::Ptr& c, bool sorted = true) : pcl_tree(sorted) {
    direct.setSortedResults(sorted);
    direct.setInputCloud(c);
    pcl_tree.setInputCloud(c);
  }
};

// `rows` profiles of `cols` points 2 um apart on a wavy surface, every 50th point a stray one
// (an outlier) and every 61st a missing one (NaN), as a line scanner gives them.
PclCloud::Ptr profiles(int rows, int cols, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  PclCloud::Ptr c(new PclCloud);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < cols; ++i) {
      PointT p;
      p.x = 0.002f * float(i), p.y = 0.01f * float(r), p.z = 0.05f * std::sin(3.f * p.x + p.y);
      if ((r * cols + i) % 50 == 7) p.z += 0.2f * u(rng);
      if ((r * cols + i) % 61 == 3) p.z = std::numeric_limits<float>::quiet_NaN();
      c->push_back(p);
    }
  c->is_dense = false;
  return c;
}

laserfit::PointCloud to_cloud(const PclCloud& in) {
  laserfit::PointCloud c;
  for (const auto& p : in) c.points.push_back(p.getVector3fMap());
  return c;
}

PointT query(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.1f, 1.1f);
  PointT q;
  q.x = u(rng), q.y = u(rng), q.z = 0.2f * u(rng);
  return q;
}

}  // namespace

TEST(Search, RadiusSearchEqualsPclExactly) {
  for (bool sorted : {true, false}) {
    Both t(random_cloud(5000, 1, true), sorted);
    std::mt19937 rng(2);
    for (int i = 0; i < 300; ++i) {
      const PointT q = query(rng);
      for (double r : {0.0, 0.03, 0.1, 0.4})
        for (unsigned max_nn : {0u, 1u, 7u, 100000u}) {
          pcl::Indices a, b;
          std::vector<float> da, db;
          const int na = t.direct.radiusSearch(q, r, a, da, max_nn);
          const int nb = t.pcl_tree.radiusSearch(q, r, b, db, max_nn);
          ASSERT_EQ(na, nb) << "r " << r << " max_nn " << max_nn;
          ASSERT_EQ(a, b) << "r " << r << " max_nn " << max_nn << " sorted " << sorted;
          ASSERT_EQ(da, db);
        }
    }
  }
}

TEST(Search, NearestKSearchEqualsPclExactly) {
  Both t(random_cloud(5000, 3, true));
  std::mt19937 rng(4);
  for (int i = 0; i < 300; ++i) {
    const PointT q = query(rng);
    for (int k : {1, 5, 30, 251, 400}) {  // 251 and 400: FLANN's heap result set (k > 250)
      pcl::Indices a, b;
      std::vector<float> da, db;
      ASSERT_EQ(t.direct.nearestKSearch(q, k, a, da), t.pcl_tree.nearestKSearch(q, k, b, db));
      ASSERT_EQ(a, b) << "k " << k;
      ASSERT_EQ(da, db);
    }
  }
  // k above the cloud's size is capped to it, as PCL does.
  Both small(random_cloud(20, 5, false));
  pcl::Indices a, b;
  std::vector<float> da, db;
  EXPECT_EQ(small.direct.nearestKSearch(query(rng), 50, a, da), 20);
  EXPECT_EQ(small.pcl_tree.nearestKSearch(query(rng), 50, b, db), 20);
}

TEST(Search, NonFiniteQueriesFindNothingInsteadOfAborting) {
  Both t(random_cloud(200, 6, false));
  PointT q;
  q.x = std::numeric_limits<float>::quiet_NaN(), q.y = q.z = 0;
  pcl::Indices idx;
  std::vector<float> d2;
  EXPECT_EQ(t.direct.radiusSearch(q, 0.5, idx, d2), 0);
  EXPECT_TRUE(idx.empty());
  ASSERT_EQ(t.direct.nearestKSearch(q, 3, idx, d2), 1);
  EXPECT_TRUE(std::isinf(d2[0]));
}

TEST(Search, ANewInputCloudIsSearchedNotTheOldOne) {
  Tree t;
  t.setInputCloud(random_cloud(500, 7, false));
  pcl::Indices idx;
  std::vector<float> d2;
  PointT q;
  q.x = q.y = q.z = 0;
  t.nearestKSearch(q, 1, idx, d2);  // builds the direct index on the first cloud
  PclCloud::Ptr far(new PclCloud);
  PointT p;
  p.x = 10, p.y = p.z = 0;
  far->push_back(p), far->push_back(p);
  far->back().x = 20;
  t.setInputCloud(far);
  ASSERT_EQ(t.nearestKSearch(q, 1, idx, d2), 1);
  EXPECT_EQ(idx[0], 0);
  EXPECT_FLOAT_EQ(d2[0], 100.f);
}

TEST(Search, BatchedQueriesEqualSinglePointOnes) {
  const auto c = random_cloud(3000, 8, true);
  Tree t;
  t.setInputCloud(c);
  std::mt19937 rng(9);
  std::vector<Eigen::Vector3f> qs;
  for (int i = 0; i < 500; ++i) qs.push_back(query(rng).getVector3fMap());
  qs.push_back(Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  std::vector<int> idx;
  std::vector<float> d2;
  t.nearest_batch(qs, idx, d2);
  std::vector<Eigen::Vector3f> pts;
  for (const auto& p : *c) pts.push_back(p.getVector3fMap());
  const double r = 0.02;
  const auto near = within_radius(pts, qs, r);
  for (size_t i = 0; i + 1 < qs.size(); ++i) {
    PointT q;
    q.getVector3fMap() = qs[i];
    pcl::Indices one;
    std::vector<float> d;
    t.nearestKSearch(q, 1, one, d);
    ASSERT_EQ(idx[i], one[0]);
    ASSERT_EQ(d2[i], d[0]);
    // Within the radius exactly when the nearest point is (strictly, as FLANN's result sets).
    ASSERT_EQ(bool(near[i]), d[0] < float(r * r)) << i;
  }
  EXPECT_EQ(idx.back(), -1);
  EXPECT_FALSE(near.back());
}

// The grid within_radius answers exactly as the kd-tree one, for radii from below the points'
// spacing to most of the cloud's size, queries inside, near and far from it; and a grid that
// would be too large (points 1 km apart at a 1 um radius) falls back to the kd-tree.
TEST(Search, GridWithinRadiusEqualsTheKdTree) {
  const auto c = random_cloud(5000, 12, true);
  std::vector<Eigen::Vector3f> pts;
  for (const auto& p : *c) pts.push_back(p.getVector3fMap());
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-3.f, 3.f);
  std::vector<Eigen::Vector3f> qs;
  for (int i = 0; i < 4000; ++i) qs.emplace_back(u(rng), u(rng), u(rng));
  for (size_t i = 0; i < 2000; ++i) qs.push_back(pts[i * 2] + Eigen::Vector3f(1e-3f, 0, 0));
  qs.push_back(Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  for (const double r : {0.001, 0.01, 0.05, 0.3, 2.0}) {
    SCOPED_TRACE(r);
    const auto grid = within_radius(pts, qs, r), tree = within_radius_kdtree(pts, qs, r);
    ASSERT_EQ(grid, tree);
    EXPECT_EQ(grid.back(), 0);  // the NaN query
  }
  const std::vector<Eigen::Vector3f> far = {{0, 0, 0}, {1e6f, 0, 0}};
  const std::vector<Eigen::Vector3f> at = {{0, 0, 0.0005f}, {1e6f, 0.002f, 0}};
  EXPECT_EQ(within_radius(far, at, 0.001), (std::vector<char>{1, 0}));
}

// uniform_sample keeps the points pcl::UniformSampling keeps, in its order, bit for bit: random
// points (with NaNs, negative coordinates), points on a lattice (ties to the voxel centre, points
// on voxel borders), profiles (runs of neighbours in one voxel, as a line scanner gives them),
// voxels from far below to above the points' spacing. Tolerance: none.
TEST(Search, UniformSampleEqualsPcl) {
  auto lattice = random_cloud(0, 1, false);
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j)
      for (const float z : {-0.25f, 0.f, 0.125f}) {
        PointT p;
        p.x = 0.05f * float(i) - 1.f, p.y = 0.025f * float(j) - 0.5f, p.z = z;
        lattice->push_back(p);
      }
  for (const auto& cloud : {random_cloud(20000, 21, true), lattice, profiles(40, 500, 22)})
    for (const double voxel : {0.0005, 0.01, 0.05, 0.1, 0.37, 5.0}) {
      SCOPED_TRACE(voxel);
      laserfit::PointCloud c;
      PclCloud::Ptr finite(new PclCloud);
      for (const auto& p : *cloud) {
        c.points.push_back(p.getVector3fMap());
        if (p.getVector3fMap().allFinite()) finite->push_back(p);
      }
      pcl::UniformSampling<PointT> us;
      us.setInputCloud(finite);
      us.setRadiusSearch(voxel);
      PclCloud expected;
      us.filter(expected);
      const auto mine = to_pcl(c, uniform_sample(c.points, voxel));
      ASSERT_EQ(mine->size(), expected.size());
      for (size_t i = 0; i < expected.size(); ++i)
        ASSERT_EQ(Eigen::Vector3f(mine->at(i).getVector3fMap()),
                  Eigen::Vector3f(expected[i].getVector3fMap()))
            << i;
    }
  // A point 10^30 mm away (a hostile file) is sampled without undefined behaviour (UBSan): the
  // grid's keys wrap, as PCL's, so which points share a voxel is arbitrary, but one is kept.
  const std::vector<Eigen::Vector3f> far = {{0, 0, 0}, {1e30f, -1e30f, 0}, {0.001f, 0, 0}};
  const size_t kept = uniform_sample(far, 0.01).size();
  EXPECT_GE(kept, 1u);
  EXPECT_LE(kept, 2u);
}

// The bounded nearest_batch (match's gate) answers exactly as the unbounded one wherever the
// nearest point is within the bound, and nothing elsewhere: random points, a lattice (equally near
// points: the same one of them must be chosen) and a query exactly at the bound. Tolerance: none.
TEST(Search, BoundedNearestEqualsUnboundedWithinTheBound) {
  auto lattice = random_cloud(0, 1, false);
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      PointT p;
      p.x = 0.125f * float(i), p.y = 0.125f * float(j), p.z = 0;
      lattice->push_back(p);
    }
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(-1.f, 4.f);
  std::vector<Eigen::Vector3f> qs;
  for (int i = 0; i < 3000; ++i) qs.emplace_back(u(rng), u(rng), 0.1f * u(rng));
  for (int i = 0; i < 200; ++i)  // midway between lattice points: ties
    qs.emplace_back(0.0625f * float(2 * (i % 29) + 1), 0.125f * float(i % 7), 0.f);
  qs.emplace_back(0.f, 0.f, 0.25f);  // exactly at the bound 0.0625 mm^2 from the lattice's corner
  for (const auto& cloud : {random_cloud(4000, 30, true), lattice}) {
    Tree t;
    t.setInputCloud(cloud);
    std::vector<int> all, within;
    std::vector<float> d_all, d_within;
    t.nearest_batch(qs, all, d_all);
    for (const float bound : {0.0625f, 0.01f, 1.f}) {
      SCOPED_TRACE(bound);
      t.nearest_batch(qs, within, d_within, bound);
      for (size_t i = 0; i < qs.size(); ++i) {
        if (d_all[i] <= bound) {
          ASSERT_EQ(within[i], all[i]) << i;
          ASSERT_EQ(d_within[i], d_all[i]) << i;
        } else {
          ASSERT_EQ(within[i], -1) << i;
        }
      }
    }
  }
}

// sample_and_filter keeps what pcl::UniformSampling then pcl::StatisticalOutlierRemoval keep, in
// their order, bit for bit: profiles with stray points, random points, filters from lenient to
// strict. Tolerance: none.
TEST(Search, OutlierRemovalEqualsPcl) {
  for (const auto& cloud : {profiles(30, 400, 41), random_cloud(5000, 42, true)})
    for (const double std_mul : {0.5, 1.0, 2.0})
      for (const int k : {5, 20}) {
        SCOPED_TRACE(std_mul);
        SCOPED_TRACE(k);
        const laserfit::PointCloud c = to_cloud(*cloud);
        PreprocessSettings pre;
        pre.outlier_std = std_mul, pre.outlier_neighbours = k;
        const double voxel = 0.004;
        const auto mine = sample_and_filter(c, pre, voxel);
        pcl::StatisticalOutlierRemoval<PointT> sor;
        sor.setInputCloud(to_pcl(c, uniform_sample(c.points, voxel)));
        sor.setMeanK(k);
        sor.setStddevMulThresh(std_mul);
        PclCloud expected;
        sor.filter(expected);
        ASSERT_LT(expected.size(), sor.getInputCloud()->size());  // the filter removed some
        ASSERT_EQ(mine->size(), expected.size());
        for (size_t i = 0; i < expected.size(); ++i)
          ASSERT_EQ(Eigen::Vector3f(mine->at(i).getVector3fMap()),
                    Eigen::Vector3f(expected[i].getVector3fMap()))
              << i;
      }
}

// euclidean_clusters gives pcl::EuclideanClusterExtraction's clusters in its order: blobs of
// equal sizes (the order among them is std::sort's, as PCL's), blobs below the minimum size,
// random points at tolerances from none joined to all joined. Tolerance: none.
TEST(Search, EuclideanClustersEqualPcl) {
  PclCloud::Ptr blobs(new PclCloud);
  std::mt19937 rng(51);
  std::uniform_real_distribution<float> u(0.f, 0.05f);
  for (int b = 0; b < 40; ++b)
    for (int i = 0; i < (b % 3 == 0 ? 30 : b % 3 == 1 ? 12 : 30 + b); ++i) {
      PointT p;
      p.x = float(b % 8) + u(rng), p.y = float(b / 8) + u(rng), p.z = u(rng);
      blobs->push_back(p);
    }
  for (const auto& cloud : {blobs, random_cloud(2000, 52, false)})
    for (const double tol : {0.01, 0.04, 0.2, 1.2}) {
      SCOPED_TRACE(tol);
      const auto mine = euclidean_clusters(cloud, tol, 20);
      pcl::EuclideanClusterExtraction<PointT> ec;
      ec.setClusterTolerance(tol);
      ec.setMinClusterSize(20);
      ec.setMaxClusterSize(int(cloud->size()));
      ec.setSearchMethod(pcl::search::KdTree<PointT>::Ptr(new pcl::search::KdTree<PointT>));
      ec.setInputCloud(cloud);
      std::vector<pcl::PointIndices> expected;
      ec.extract(expected);
      ASSERT_EQ(mine.size(), expected.size());
      for (size_t k = 0; k < expected.size(); ++k)
        ASSERT_EQ(mine[k].indices, expected[k].indices) << k;
    }
}
