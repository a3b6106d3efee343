// Reference-cloud sampling: on the surface, uniform by area, exact counts, Poisson-disk spacing,
// seeded and thread-count independent; view-dependent clouds follow the scanner's visibility.
#include <gtest/gtest.h>

#include <cmath>

#include "laserfit/core/error.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "test_util.hpp"

using namespace laserfit;
using sampling::Method;

namespace {
const TriMesh kBox = test::box_mesh({0, 0, 0}, {10, 20, 30});  // faces: 200, 300, 600 mm^2 pairs

sampling::SamplingSettings count(size_t n, Method m = Method::Uniform, uint64_t seed = 1) {
  sampling::SamplingSettings s;
  s.count = n;
  s.method = m;
  s.seed = seed;
  return s;
}

// Smallest distance from each point to any other (brute force, small clouds only).
std::vector<double> nn_distances(const PointCloud& c) {
  std::vector<double> d(c.size(), 1e30);
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = 0; j < c.size(); ++j)
      if (i != j) d[i] = std::min(d[i], double((c.points[i] - c.points[j]).norm()));
  return d;
}
}  // namespace

TEST(Uniform, PointsLieOnTheSurfaceWithFaceNormals) {
  const auto c = sampling::sample_uniform(kBox, count(100000));
  ASSERT_EQ(c.size(), 100000u);
  for (size_t i = 0; i < c.size(); ++i) {
    const Eigen::Vector3f& p = c.points[i];
    // Tolerance 1e-5 mm: float rounding of coordinates up to 30 mm.
    const float d = std::min({std::abs(p.x()), std::abs(p.x() - 10), std::abs(p.y()),
                              std::abs(p.y() - 20), std::abs(p.z()), std::abs(p.z() - 30)});
    ASSERT_LT(d, 1e-5f) << p.transpose();
    ASSERT_NEAR(c.normals[i].norm(), 1.f, 1e-6f);
  }
}

TEST(Uniform, FacesGetPointsInProportionToArea) {
  const size_t n = 200000;
  const auto c = sampling::sample_uniform(kBox, count(n));
  size_t on_z = 0, on_y = 0, on_x = 0;
  for (const auto& nrm : c.normals) {
    on_z += std::abs(nrm.z()) > 0.5f, on_y += std::abs(nrm.y()) > 0.5f,
        on_x += std::abs(nrm.x()) > 0.5f;
  }
  // Expected fractions 400/2200, 600/2200, 1200/2200; tolerance 5 binomial sigmas.
  for (auto [got, p] : {std::pair{on_z, 400.0 / 2200}, {on_y, 600.0 / 2200}, {on_x, 1200.0 / 2200}})
    EXPECT_NEAR(double(got) / n, p, 5 * std::sqrt(p * (1 - p) / n));
}

TEST(Uniform, DensityGivesPointsPerSquareMillimetre) {
  sampling::SamplingSettings s;
  s.density_per_mm2 = 10;
  EXPECT_EQ(sampling::sample_uniform(kBox, s).size(), 22000u);
  s.count = 5;  // both: refused
  EXPECT_THROW(sampling::sample_uniform(kBox, s), Error);
}

TEST(Uniform, SameSeedSameBytesWhateverTheThreadCount) {
  auto run = [] { return sampling::sample_uniform(kBox, count(50000, Method::Uniform, 42)); };
  const PointCloud one = test::with_threads(1, run), two = test::with_threads(2, run);
  EXPECT_EQ(one.points, two.points);
  EXPECT_EQ(one.metadata.at("seed"), "42");
  EXPECT_NE(sampling::sample_uniform(kBox, count(50000, Method::Uniform, 43)).points, one.points);
}

TEST(PoissonDisk, ExactCountAndEvenSpacing) {
  const size_t n = 2000;
  const auto p = sampling::sample_poisson_disk(kBox, count(n, Method::PoissonDisk));
  const auto u = sampling::sample_uniform(kBox, count(n));
  ASSERT_EQ(p.size(), n);
  const double r_max = std::sqrt(2200.0 / (2 * std::sqrt(3.0) * n));  // Yuksel eq. 5
  const auto dp = nn_distances(p), du = nn_distances(u);
  // Sample elimination guarantees no close pairs: every nearest neighbour beyond 0.5 r_max,
  // where i.i.d. sampling has pairs at a few percent of it.
  EXPECT_GT(*std::min_element(dp.begin(), dp.end()), 0.5 * r_max);
  EXPECT_LT(*std::min_element(du.begin(), du.end()), 0.1 * r_max);
}

TEST(PoissonDisk, ThreadCountIndependent) {
  auto run = [] {
    return sampling::sample_poisson_disk(kBox, count(3000, Method::PoissonDisk, 5));
  };
  const PointCloud one = test::with_threads(1, run), two = test::with_threads(2, run);
  EXPECT_EQ(one.points, two.points);
}

namespace {
sampling::ViewSettings from_above(const TriMesh& m, double margin = 5.0) {
  sampling::ViewSettings v;
  const Eigen::Vector3d top(m.bbox().center().x(), m.bbox().center().y(), m.bbox().max().z());
  v.T_mesh_sensor.push_back(
      look_at(top + Eigen::Vector3d(0, 0, v.geometry.z_min_mm + margin), top));
  return v;
}
}  // namespace

TEST(Visible, BoxSeenFromAboveShowsOnlyItsTop) {
  const TriMesh cube = test::box_mesh({-5, -5, -5}, {5, 5, 5});
  const auto c = sampling::sample_visible(cube, from_above(cube), count(20000));
  ASSERT_EQ(c.size(), 20000u);
  for (size_t i = 0; i < c.size(); ++i) {
    ASSERT_NEAR(c.points[i].z(), 5.f, 1e-5f);
    ASSERT_GT(c.normals[i].z(), 0.999f);
  }
  // Visible area estimate: the 100 mm^2 top, to within 4 % (sampling noise of 1/6 of draws).
  EXPECT_NEAR(std::stod(c.metadata.at("visible_area_mm2")), 100.0, 4.0);
}

TEST(Visible, CameraShadowFallsBehindAStep) {
  // A 5 mm block on a plate. The camera sits on the sensor's +y side of the laser plane, so the
  // block hides the plate from it on the opposite side, over 5 mm x baseline / camera height.
  TriMesh scene = test::box_mesh({-15, -15, -1}, {15, 15, 0});
  scene.append(test::box_mesh({-5, -5, 0}, {5, 5, 5}));
  auto views = from_above(scene, 8.0);
  const auto c = sampling::sample_visible(scene, views, count(60000));
  const double baseline = views.geometry.baseline_mm();
  const double sensor_h = views.T_mesh_sensor[0].translation().z();  // above the plate (z = 0)
  const double shadow = 5.0 * baseline / sensor_h;                   // similar triangles
  // World direction of the camera from the laser plane; the shadow is on the other side.
  const float away = views.T_mesh_sensor[0].linear()(1, 1) > 0 ? -1.f : 1.f;
  size_t in_shadow = 0, lit = 0;
  for (const auto& p : c.points) {
    if (std::abs(p.z()) > 1e-4f || std::abs(p.x()) > 4.f) continue;  // plate, beside the block
    const float y = away * p.y();  // > 5: the side facing away from the camera
    if (y > 5.05f && y < 5.f + shadow - 0.05f) ++in_shadow;
    if (-y > 5.05f && -y < 5.f + shadow - 0.05f) ++lit;
  }
  EXPECT_GT(shadow, 2.0);
  EXPECT_EQ(in_shadow, 0u) << "shadow band of " << shadow << " mm behind the step";
  EXPECT_GT(lit, 100u) << "the camera side of the step is seen";
}

TEST(Visible, ViewsAreMergedAndImpossibleViewsRejected) {
  const TriMesh cube = test::box_mesh({-5, -5, -5}, {5, 5, 5});
  auto v = from_above(cube);
  v.T_mesh_sensor.push_back(look_at({0, 0, -5 - v.geometry.z_min_mm - 5}, {0, 0, -5}));
  const auto c = sampling::sample_visible(cube, v, count(10000));
  size_t top = 0, bottom = 0;
  for (const auto& n : c.normals) top += n.z() > 0.99f, bottom += n.z() < -0.99f;
  EXPECT_EQ(top + bottom, c.size());
  EXPECT_NEAR(double(top) / c.size(), 0.5, 0.05);
  sampling::ViewSettings away;
  away.T_mesh_sensor.push_back(look_at({0, 0, 200}, {0, 0, 400}));  // looking away from the part
  EXPECT_THROW(sampling::sample_visible(cube, away, count(100)), Error);
}

TEST(Visible, ThreadCountIndependent) {
  const TriMesh cube = test::box_mesh({-5, -5, -5}, {5, 5, 5});
  auto run = [&] {
    return sampling::sample_visible(cube, from_above(cube), count(5000, Method::PoissonDisk, 9));
  };
  const PointCloud one = test::with_threads(1, run), two = test::with_threads(2, run);
  EXPECT_EQ(one.points, two.points);
}
