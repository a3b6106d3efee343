// The prepared-reference memo (lib/registration/src/reference_cache.hpp): hits by content, not by
// address; misses on any setting it depends on; and what it returns equals a fresh preparation.
#include <gtest/gtest.h>

#include "laserfit/cad/import.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "reference_cache.hpp"

using namespace laserfit;
namespace reg = laserfit::registration;

namespace {
PointCloud plug_reference(uint64_t seed) {
  const TriMesh m = cad::import_cad(std::string(LASERFIT_SOURCE_DIR) + "/cad/usb_a_plug.ply").mesh;
  sampling::SamplingSettings s;
  s.count = 20000, s.seed = seed;
  return sampling::sample_uniform(m, s);
}
}  // namespace

TEST(ReferenceCache, HitsByContentAndMissesOnItsSettings) {
  const PointCloud a = plug_reference(5);
  const PointCloud copy = a;  // another address, same bytes
  const reg::RegistrationSettings s;
  const auto pa = reg::prepared_reference(a, s, 0.05, true);
  EXPECT_EQ(reg::prepared_reference(copy, s, 0.05, true), pa);
  EXPECT_NE(reg::prepared_reference(a, s, 0.06, true), pa);   // voxel
  EXPECT_NE(reg::prepared_reference(a, s, 0.05, false), pa);  // without features
  reg::RegistrationSettings r = s;
  r.coarse.feature_radius_vox = 5;
  EXPECT_NE(reg::prepared_reference(a, r, 0.05, true), pa);
  PointCloud moved = a;
  moved.points[7].x() += 1e-3f;  // one point 1 um off
  EXPECT_NE(reg::prepared_reference(moved, s, 0.05, true), pa);
  // A cloud without normals is another reference (its normals are estimated).
  PointCloud bare = a;
  bare.normals.clear();
  const auto pb = reg::prepared_reference(bare, s, 0.05, true);
  EXPECT_NE(pb, pa);
  ASSERT_TRUE(pa->features && pb->features);
}

TEST(ReferenceCache, EntriesEqualAFreshPreparation) {
  const PointCloud a = plug_reference(6);
  const reg::RegistrationSettings s;
  const auto first = reg::prepared_reference(a, s, 0.05, true);
  for (uint64_t k = 0; k < 10; ++k) reg::prepared_reference(plug_reference(100 + k), s, 0.05, true);
  const auto again = reg::prepared_reference(a, s, 0.05, true);  // aged out: prepared afresh
  ASSERT_NE(again, first);
  ASSERT_EQ(again->ref->size(), first->ref->size());
  ASSERT_EQ(again->features->size(), first->features->size());
  for (size_t i = 0; i < first->features->size(); ++i)
    for (int j = 0; j < 33; ++j)
      ASSERT_EQ((*again->features)[i].histogram[j], (*first->features)[i].histogram[j]) << i;
}
