// Cloud files: our binary PCD/PLY writers round-trip through PCL's readers, metadata included;
// bad files are refused with one clear error naming the file.
#include <gtest/gtest.h>

#include <cmath>

#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/json.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {
PointCloud small_cloud(bool organized) {
  PointCloud c;
  for (int i = 0; i < 12; ++i) {
    c.points.emplace_back(0.001f * i, 2.f * i, -3.5f + i);
    c.normals.emplace_back(0.f, 0.f, 1.f);
  }
  if (organized) {
    c.points[5] = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
    c.width = 4, c.height = 3;
  } else {
    c.width = 12;
  }
  c.metadata["seed"] = "17";
  c.metadata["source"] = "a file\nwith a newline";
  return c;
}
}  // namespace

TEST(CloudIo, PcdAndPlyRoundTripBitExact) {
  test::TempDir dir;
  for (const char* name : {"c.pcd", "c.ply"}) {
    for (bool organized : {false, true}) {
      SCOPED_TRACE(std::string(name) + (organized ? " organized" : ""));
      const PointCloud c = small_cloud(organized);
      io::write_cloud(dir / name, c);
      const PointCloud r = io::read_cloud(dir / name);
      ASSERT_EQ(r.size(), c.size());
      for (size_t i = 0; i < c.size(); ++i) {
        if (!c.points[i].allFinite()) {
          EXPECT_TRUE(std::isnan(r.points[i].x()));
          continue;
        }
        EXPECT_EQ(r.points[i], c.points[i]);  // binary float: exact
        EXPECT_EQ(r.normals[i], c.normals[i]);
      }
      if (std::string(name) == "c.pcd") {
        EXPECT_EQ(r.height, c.height);
      }
      EXPECT_EQ(r.metadata.at("seed"), "17");
      EXPECT_EQ(r.metadata.at("source"), "a file with a newline");
    }
  }
}

TEST(CloudIo, RefusesBadFiles) {
  test::TempDir dir;
  io::write_cloud(dir / "good.pcd", small_cloud(false));
  const std::string good = test::read_bytes(dir / "good.pcd");
  test::write_text(dir / "truncated.pcd", good.substr(0, good.size() - 20));
  test::write_text(dir / "empty.pcd", "");
  test::write_text(dir / "garbage.pcd", "not a point cloud at all\n");
  test::write_text(dir / "garbage.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  for (const char* f :
       {"truncated.pcd", "empty.pcd", "garbage.pcd", "garbage.ply", "missing.pcd"}) {
    SCOPED_TRACE(f);
    try {
      io::read_cloud(dir / f);
      FAIL() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(io::write_cloud(dir / "x.xyz", small_cloud(false)), Error);
  EXPECT_THROW(io::write_cloud(dir / "empty_out.pcd", PointCloud{}), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "empty_out.pcd"));
}

TEST(Json, PoseRoundTrip) {
  const Pose T = parse_pose("1.5 -2 3.25 0.5 0.5 0.5 0.5");
  const Pose back = io::pose_from_json(io::pose_to_json(T), "test");
  EXPECT_NEAR((T.matrix() - back.matrix()).norm(), 0, 1e-15);
}
