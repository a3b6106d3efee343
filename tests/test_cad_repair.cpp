// Mesh checks and repair (CGAL) on meshes with known defects; every count is exact.
#include <gtest/gtest.h>

#include "laserfit/cad/repair.hpp"
#include "laserfit/core/error.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {
TriMesh unit_box() { return test::box_mesh({0, 0, 0}, {1, 1, 1}); }

// The same box as an STL-like soup: three private vertices per triangle.
TriMesh soup(const TriMesh& m) {
  TriMesh s;
  for (const auto& f : m.faces) {
    const int base = static_cast<int>(s.vertices.size());
    for (int k = 0; k < 3; ++k) s.vertices.push_back(m.vertices[f[k]]);
    s.faces.emplace_back(base, base + 1, base + 2);
  }
  return s;
}
}  // namespace

TEST(Repair, CleanBoxIsWatertightWithUnitVolume) {
  TriMesh m = unit_box();
  const auto r = cad::check_and_repair(m, {}, "box");
  EXPECT_TRUE(r.watertight);
  EXPECT_TRUE(r.outward);
  EXPECT_NEAR(r.volume_mm3, 1.0, 1e-12);
  EXPECT_EQ(r.faces_reoriented, 0u);
  EXPECT_EQ(r.self_intersecting_pairs, 0u);
}

TEST(Repair, MergesDuplicatesDropsDegenerateAndDuplicateFaces) {
  TriMesh m = soup(unit_box());             // 36 vertices, 8 distinct -> 28 merged
  m.faces.push_back(m.faces[0]);            // duplicate face
  m.vertices.emplace_back(0.5f, 0.f, 0.f);  // collinear with vertices (0,0,0),(1,0,0)
  m.faces.emplace_back(
      0, 1, static_cast<int>(m.vertices.size()) - 1);  // face 0 is (0,0,0),(0,1,0),(1,0,0)
  m.faces.emplace_back(0, 0, 1);                       // repeated vertex
  const auto r = cad::check_and_repair(m, {}, "soup");
  EXPECT_EQ(r.duplicate_vertices_merged, 28u);
  EXPECT_EQ(r.duplicate_faces_removed, 1u);
  EXPECT_EQ(r.degenerate_faces_removed,
            1u);                   // the repeated-vertex face; (0,1,new) is not collinear
  EXPECT_EQ(m.faces.size(), 13u);  // the extra non-degenerate triangle stays
}

TEST(Repair, CollinearFaceIsRemoved) {
  TriMesh m = unit_box();
  m.vertices.emplace_back(0.5f, 0.f, 0.f);
  m.faces.emplace_back(0, 1, 8);  // (0,0,0), (1,0,0), (0.5,0,0): zero area
  const auto r = cad::check_and_repair(m, {}, "box");
  EXPECT_EQ(r.degenerate_faces_removed, 1u);
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_TRUE(r.watertight);
}

TEST(Repair, FlippedFacesAreReorientedOutward) {
  TriMesh m = unit_box();
  std::swap(m.faces[3][1], m.faces[3][2]);
  std::swap(m.faces[7][1], m.faces[7][2]);
  const auto r = cad::check_and_repair(m, {}, "box");
  EXPECT_EQ(r.faces_reoriented, 2u);
  EXPECT_NEAR(r.volume_mm3, 1.0, 1e-12);
  // All faces now point away from the centre.
  for (int f = 0; f < 12; ++f) {
    const auto& t = m.faces[f];
    const Eigen::Vector3f c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3;
    EXPECT_GT(m.face_normal(f).dot(c - Eigen::Vector3f(0.5f, 0.5f, 0.5f)), 0.f);
  }
}

TEST(Repair, InsideOutBoxIsTurnedOutward) {
  TriMesh m = unit_box();
  for (auto& f : m.faces) std::swap(f[1], f[2]);
  const auto r = cad::check_and_repair(m, {}, "box");
  EXPECT_EQ(r.faces_reoriented, 12u);
  EXPECT_NEAR(r.volume_mm3, 1.0, 1e-12);
}

TEST(Repair, HolesAreReportedAndFilledOnRequest) {
  TriMesh m = unit_box();
  m.faces.erase(m.faces.begin(), m.faces.begin() + 2);  // remove the bottom square
  TriMesh copy = m;
  const auto open = cad::check_and_repair(copy, {}, "box");
  EXPECT_FALSE(open.watertight);
  EXPECT_EQ(open.holes, 1u);
  EXPECT_EQ(open.boundary_edges, 4u);
  cad::RepairSettings fill;
  fill.fill_holes = true;
  const auto filled = cad::check_and_repair(m, fill, "box");
  EXPECT_EQ(filled.holes_filled, 1u);
  EXPECT_EQ(filled.holes, 0u);
  EXPECT_TRUE(filled.watertight);
  EXPECT_NEAR(filled.volume_mm3, 1.0, 1e-12);
}

TEST(Repair, NonManifoldEdgeIsCountedAndSplit) {
  TriMesh m = unit_box();
  m.vertices.emplace_back(0.5f, -1.f, 0.5f);  // a fin hanging on the edge (0,0,0)-(1,0,0)
  m.faces.emplace_back(0, 1, 8);
  const auto r = cad::check_and_repair(m, {}, "fin");
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_FALSE(r.watertight);
}

TEST(Repair, SelfIntersectionsAreCounted) {
  TriMesh m = unit_box();
  const TriMesh other = test::box_mesh({0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f});
  m.append(other);  // two overlapping closed boxes
  const auto r = cad::check_and_repair(m, {}, "boxes");
  EXPECT_GT(r.self_intersecting_pairs, 0u);
  EXPECT_FALSE(r.outward);  // orientation of an intersecting surface is not decided
}

TEST(Repair, CheckOnlyLeavesTheMeshAlone) {
  TriMesh m = soup(unit_box());
  const TriMesh before = m;
  cad::RepairSettings s;
  s.repair = false;
  const auto r = cad::check_and_repair(m, s, "soup");
  EXPECT_EQ(r.duplicate_vertices_merged, 28u);
  EXPECT_EQ(m.vertices.size(), before.vertices.size());
}

TEST(Repair, RejectsUnusableMeshes) {
  TriMesh empty;
  EXPECT_THROW(cad::check_and_repair(empty, {}, "e"), Error);
  TriMesh nan = unit_box();
  nan.vertices[3].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(cad::check_and_repair(nan, {}, "n"), Error);
  TriMesh bad_index = unit_box();
  bad_index.faces[0][1] = 99;
  EXPECT_THROW(cad::check_and_repair(bad_index, {}, "i"), Error);
}
