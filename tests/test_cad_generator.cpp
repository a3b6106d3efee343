// The project's parametric CAD: dimensions measured on the generated meshes, validity, determinism
// and that the committed files in cad/ are what the generator makes today.
#include <gtest/gtest.h>

#include <filesystem>

#include "laserfit/cad/generator.hpp"
#include "laserfit/cad/repair.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/raycast/scene.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {
const TriMesh& part(const cad::GeneratedModel& g, const std::string& name) {
  for (const auto& p : g.parts)
    if (p.name == name) return p.mesh;
  throw Error("no part " + name);
}

// Does a ray along z through (x, y) pass the needle without hitting it?
bool passes(const raycast::Scene& s, float x, float y) {
  return !s.intersect({x, y, -5.f}, {0, 0, 1}, 0.f, 10.f).valid();
}
}  // namespace

TEST(Generator, EveryPartIsWatertightAndOutward) {
  for (const auto& info : cad::model_catalogue()) {
    const auto g = cad::generate_model(info.name);
    for (const auto& p : g.parts) {
      SCOPED_TRACE(p.name);
      TriMesh m = p.mesh;
      const auto r = cad::check_and_repair(m, {}, p.name);
      EXPECT_TRUE(r.watertight);
      EXPECT_TRUE(r.outward);
      EXPECT_EQ(r.self_intersecting_pairs, 0u);
      EXPECT_EQ(r.faces_reoriented, 0u) << "generator winding is already outward";
      EXPECT_GT(r.volume_mm3, 0.0);
    }
  }
}

TEST(Generator, NeedleEyeHasTheConfiguredWidth) {
  // Probe the eye with rays along z: open inside the slot, closed 10 um outside it.
  for (double w : {0.30, 0.35}) {
    SCOPED_TRACE(w);
    const auto g = cad::generate_model("needle", {{"eye_width", w}});
    raycast::Scene s;
    s.add_mesh(part(g, "needle"));
    s.commit();
    const float half = static_cast<float>(w / 2);
    EXPECT_TRUE(passes(s, 0.f, 0.f));
    EXPECT_TRUE(passes(s, 0.f, half - 0.01f));
    EXPECT_FALSE(passes(s, 0.f, half + 0.01f));
    EXPECT_FALSE(passes(s, 0.f, -half - 0.01f));
    EXPECT_TRUE(passes(s, 0.45f, 0.f));  // eye length 1.0: open up to x = 0.5
    EXPECT_FALSE(passes(s, 0.52f, 0.f));
  }
  const auto g = cad::generate_model("needle");
  const Eigen::Vector3f t = part(g, "thread_tip").extent();
  EXPECT_NEAR(t.x(), 0.15, 0.002);  // diameter within the 2 um deflection
  EXPECT_NEAR(t.z(), 4.0, 1e-4);
}

TEST(Generator, UsbShellAndOpeningDimensions) {
  const auto g = cad::generate_model("usb_a", {{"clearance", 0.2}});
  // The plug shell is the part of the plug in front of the overmould (z > -11.5).
  Eigen::AlignedBox3f shell;
  for (const auto& v : part(g, "usb_a_plug").vertices)
    if (v.z() > -11.4f) shell.extend(v);
  EXPECT_NEAR(shell.sizes().x(), 12.0, 1e-4);
  EXPECT_NEAR(shell.sizes().y(), 4.5, 1e-4);
  // Receptacle opening: probe along +z at the mouth's inner edges (opening 12.2 x 4.7).
  raycast::Scene s;
  s.add_mesh(part(g, "usb_a_receptacle"));
  s.commit();
  auto depth = [&](float x, float y) { return s.intersect({x, y, -1.f}, {0, 0, 1}).t - 1.f; };
  EXPECT_GT(depth(6.05f, -2.3f), 5.f);    // inside the opening corner: deep
  EXPECT_LT(depth(6.15f, -2.3f), 0.01f);  // plate face just outside
}

TEST(Generator, RejectsBadParameters) {
  EXPECT_THROW(cad::generate_model("needle", {{"eye_width", 5.0}}), Error);  // out of range
  EXPECT_THROW(cad::generate_model("needle", {{"eye_widht", 0.3}}), Error);  // unknown
  EXPECT_THROW(cad::generate_model("needle", {{"eye_width", 0.6}, {"shaft_diameter", 0.6}}), Error);
  EXPECT_THROW(cad::generate_model("teapot"), Error);
}

TEST(Generator, DeterministicAndCommittedFilesUpToDate) {
  // cad/ must hold exactly what `make cad` generates (meshes and parameter files); a mismatch
  // means the generator changed without regenerating, or a committed file was edited by hand.
  test::TempDir dir;
  for (const auto& info : cad::model_catalogue()) {
    const auto a = cad::generate_model(info.name), b = cad::generate_model(info.name);
    for (size_t i = 0; i < a.parts.size(); ++i)
      ASSERT_EQ(a.parts[i].mesh.vertices, b.parts[i].mesh.vertices);
    for (const auto& file : cad::write_model(a, dir.path.string())) {
      const auto name = std::filesystem::path(file).filename().string();
      SCOPED_TRACE(name);
      const std::string committed = std::string(LASERFIT_SOURCE_DIR) + "/cad/" + name;
      EXPECT_TRUE(test::read_bytes(file) == test::read_bytes(committed))
          << committed << " is stale: run `make cad`";
    }
  }
}
