// Cloud files: our binary PCD/PLY writers round-trip through PCL's readers, metadata included;
// bad files are refused with one clear error naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/header_check.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/io/profiles.hpp"
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
  c.sensor_origin = Eigen::Vector3d(512.3, -40.700000000000003, 0.1 + 0.2);  // not 10 digits
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
      EXPECT_EQ(r.width, c.width);  // PLY too: obj_info num_cols / num_rows, as PCL reads it
      EXPECT_EQ(r.height, c.height);
      EXPECT_EQ(r.metadata.at("seed"), "17");
      ASSERT_TRUE(r.sensor_origin);
      EXPECT_EQ(*r.sensor_origin, *c.sensor_origin);  // bit-exact
      EXPECT_EQ(r.metadata.count("viewpoint"), 0u);   // one place for it: the typed field
      EXPECT_EQ(r.metadata.at("source"), "a file with a newline");
    }
  }
}

// Clouds from other tools, in their conventions: Open3D's PLY (double x y z nx ny nz, uchar
// colour, metres), a PCD whose only sensor origin is its VIEWPOINT. Points must come back in mm
// within float rounding (1e-7 relative); the unit a laserfit file states wins over the caller's.
TEST(CloudIo, ReadsOtherToolsConventions) {
  test::TempDir dir;
  const PointCloud mm = small_cloud(false);
  std::ostringstream ply;
  ply << "ply\nformat binary_little_endian 1.0\ncomment Created by Open3D\nelement vertex "
      << mm.size() << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "property double nx\nproperty double ny\nproperty double nz\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (size_t i = 0; i < mm.size(); ++i) {
    const Eigen::Vector3d p = mm.points[i].cast<double>() * 1e-3, n = mm.normals[i].cast<double>();
    ply.write(reinterpret_cast<const char*>(p.data()), 24);
    ply.write(reinterpret_cast<const char*>(n.data()), 24);
    ply.write("\x10\x20\x30", 3);
  }
  test::write_text(dir / "open3d.ply", ply.str());
  EXPECT_THROW(io::read_cloud(dir / "open3d.ply", Unit::Auto), Error);  // must be told
  const PointCloud r = io::read_cloud(dir / "open3d.ply", Unit::Metre);
  ASSERT_EQ(r.size(), mm.size());
  for (size_t i = 0; i < mm.size(); ++i) {
    EXPECT_EQ(r.points[i], mm.points[i]);  // scaled in double, rounded once: the same floats
    EXPECT_EQ(r.normals[i], mm.normals[i]);
  }
  EXPECT_EQ(r.metadata.at("unit"), "mm");
  EXPECT_EQ(r.metadata.at("unit_converted_from"), "m");

  PointCloud c = small_cloud(false);
  c.metadata.clear();  // no laserfit.* comments: the VIEWPOINT alone says where the sensor was
  io::write_cloud(dir / "laserfit.pcd", c);
  std::string pcd = test::read_bytes(dir / "laserfit.pcd");
  for (const char* line : {"# laserfit.viewpoint", "# laserfit.unit"})
    pcd.erase(pcd.find(line), pcd.find('\n', pcd.find(line)) - pcd.find(line) + 1);
  test::write_text(dir / "viewpoint.pcd", pcd);
  const PointCloud v = io::read_cloud(dir / "viewpoint.pcd", Unit::Metre);
  ASSERT_TRUE(v.sensor_origin);
  EXPECT_LE((*v.sensor_origin - *c.sensor_origin * 1e3).norm(), 1e-4 * c.sensor_origin->norm());

  PointCloud stated = small_cloud(false);  // laserfit's writer states the unit, always
  stated.metadata.clear();
  io::write_cloud(dir / "stated.pcd", stated);
  EXPECT_EQ(io::read_cloud(dir / "stated.pcd", Unit::Metre).points[3], stated.points[3]);
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
  std::string vp = good;  // a sensor origin that is not three numbers
  vp.replace(vp.find("# laserfit.viewpoint "), 21, "# laserfit.viewpoint x");
  test::write_text(dir / "bad_viewpoint.pcd", vp);
  for (const char* f : {"truncated.pcd", "empty.pcd", "garbage.pcd", "garbage.ply", "missing.pcd",
                        "bad_viewpoint.pcd"}) {
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

// Headers that would make PCL (or assimp) crash or allocate without bound are refused before any
// parser runs, with the reason; the message is checked word for word where it carries a number.
TEST(HeaderCheck, RefusesImplausibleHeadersUpFront) {
  test::TempDir dir;
  const std::string pcd = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {pcd + "WIDTH 1000000000000\nHEIGHT 1\nPOINTS 1000000000000\nDATA binary\n",
       "header claims 1000000000000 points, more than the limit of 200000000"},
      {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
       "SIZE lists 2 entries for 3 fields"},
      {pcd + "WIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n1 2 3\n",
       "WIDTH x HEIGHT does not equal POINTS"},
      {pcd + "WIDTH 100\nHEIGHT 1\nPOINTS 100\nDATA binary\n" + std::string(12 * 99, '\0'),
       "truncated: binary data shorter than POINTS"},
      {pcd + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_compressed\n" +
           std::string("\x04\x00\x00\x00\x00\x00\x00\x10zzzz", 12),
       "compressed block sizes do not match the header or the file"},
      {pcd + "WIDTH -5\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "bad WIDTH line"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string f = dir / ("c" + std::to_string(i) + ".pcd");
    test::write_text(f, cases[i].first);
    try {
      io::read_cloud(f);
      ADD_FAILURE() << "accepted case " << i;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), f + ": " + cases[i].second);
    }
  }
  const std::string ply = dir / "big.ply";
  test::write_text(ply,
                   "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty "
                   "float x\nproperty float y\nproperty float z\nend_header\n");
  EXPECT_THROW(io::read_cloud(ply), Error);
  EXPECT_THROW(io::check_mesh_header(ply, ".ply", 50'000'000), Error);
  // A binary STL whose count claims 10^9 triangles: refused on its count, before assimp.
  std::string stl(84, '\0');
  const uint32_t n = 1'000'000'000;
  std::memcpy(stl.data() + 80, &n, 4);
  test::write_text(dir / "big.stl", stl + std::string(50, '\0'));
  try {
    io::check_mesh_header(dir / "big.stl", ".stl", 50'000'000);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "big.stl") +
                                         ": header claims 1000000000 triangles, more "
                                         "than the limit of 50000000");
  }
  // An ASCII STL ("solid ...") is not mistaken for a binary one.
  test::write_text(dir / "a.stl",
                   "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                   "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_NO_THROW(io::check_mesh_header(dir / "a.stl", ".stl", 50'000'000));
  // OFF: assimp allocates its vertex and face arrays from the counts before reading a line.
  // Prefixes, comments and the n-dimension are skipped as assimp skips them.
  const std::string cube = "4 0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 3\n";
  test::write_text(dir / "ok.off", "# a comment\nCOFF\n# another\n4 2 0\n" + cube);
  EXPECT_NO_THROW(io::check_mesh_header(dir / "ok.off", ".off", 50'000'000));
  test::write_text(dir / "dim.off", "nOFF 3\n4 2 0\n" + cube);
  EXPECT_NO_THROW(io::check_mesh_header(dir / "dim.off", ".off", 50'000'000));
  const std::pair<std::string, std::string> bad[] = {
      {"OFF\n4 4222222222222220 1 3\n" + cube,
       "header claims 4222222222222220 faces, more than the limit of 50000000"},
      {"OFF 90000 2 0\n" + cube,  // a flipped digit in the vertex count
       "truncated: the OFF header announces 90000 vertices and 2 faces, one line each, in a file "
       "of 56 bytes"},
      {"nOFF 3 60000000 2 0\n",
       "header claims 60000000 vertices, more than the limit of 50000000"}};
  for (const auto& [text, why] : bad) {
    test::write_text(dir / "bad.off", text);
    try {
      io::check_mesh_header(dir / "bad.off", ".off", 50'000'000);
      ADD_FAILURE() << "accepted " << text.substr(0, 20);
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), (dir / "bad.off") + ": " + why);
    }
  }
}

TEST(Json, PoseRoundTrip) {
  const Pose T = parse_pose("1.5 -2 3.25 0.5 0.5 0.5 0.5");
  const Pose back = io::pose_from_json(io::pose_to_json(T), "test");
  EXPECT_NEAR((T.matrix() - back.matrix()).norm(), 0, 1e-15);
}

// Profiles as drivers export them: a CSV with a comment, a header row, an empty field and a "nan"
// (no measurement), in metres, both layouts; the same numbers as float32 binary. Values must come
// back exactly (scaled in double, rounded once); a row of the wrong length or a pose that is not
// rigid is one error naming the file and the row.
TEST(Profiles, CsvBinaryAndPosesInTheirUnits) {
  test::TempDir dir;
  test::write_text(dir / "p.csv",
                   "# from the driver\nx0,z0,x1,z1,x2,z2\n0.001,0.09,,0.091,0.003,0.092\n"
                   "-0.001;0.089;0.002;nan;0.003;0\n");
  io::ProfileFileSettings s;
  s.unit = Unit::Metre;
  const io::Profiles p = io::read_profiles(dir / "p.csv", s);
  ASSERT_EQ(p.width, 3);
  ASSERT_EQ(p.count, 2);
  EXPECT_EQ(p.xz[0], Eigen::Vector2f(1.f, 90.f));
  EXPECT_FALSE(p.xz[1].allFinite());  // empty x
  EXPECT_FALSE(p.xz[4].allFinite());  // nan z
  EXPECT_EQ(p.xz[5], Eigen::Vector2f(3.f, 0.f));
  s.zero_is_invalid = true;
  EXPECT_FALSE(io::read_profiles(dir / "p.csv", s).xz[5].allFinite());

  std::string wide;  // a 5000-point profile: a 90 kB row, read in more than one chunk
  for (int j = 0; j < 5000; ++j) wide += (j ? "," : "") + std::to_string(j) + ",90.125";
  test::write_text(dir / "wide.csv", wide + "\n" + wide);  // the last row without a newline
  const io::Profiles w = io::read_profiles(dir / "wide.csv", {});
  ASSERT_EQ(w.width, 5000);
  ASSERT_EQ(w.count, 2);
  EXPECT_EQ(w.xz[9999], Eigen::Vector2f(4999.f, 90.125f));

  const std::vector<float> blocks = {1, 2, 3, 90, 91, 92};  // x0 x1 x2 z0 z1 z2, mm
  test::write_text(dir / "p.bin", std::string(reinterpret_cast<const char*>(blocks.data()), 24));
  io::ProfileFileSettings b;
  b.layout = io::ProfileLayout::blocks, b.scalar = io::ProfileScalar::f32, b.width = 3;
  const io::Profiles q = io::read_profiles(dir / "p.bin", b);
  ASSERT_EQ(q.count, 1);
  EXPECT_EQ(q.xz[1], Eigen::Vector2f(2.f, 91.f));
  b.width = 4;  // 24 bytes are not whole profiles of 32
  EXPECT_THROW(io::read_profiles(dir / "p.bin", b), Error);

  test::write_text(dir / "poses.csv", "x,y,z,qw,qx,qy,qz\n0.5,0,0.25,1,0,0,0\n");
  const auto poses = io::read_pose_list(dir / "poses.csv", Unit::Metre);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].translation(), Eigen::Vector3d(500, 0, 250));

  test::write_text(dir / "short.csv", "1,90,2,91\n1,90,2\n");
  test::write_text(dir / "words.csv", "1,90\nx,z\n");
  test::write_text(dir / "bad_pose.csv", "0 0 0 2 0 0 0\n");
  test::write_text(dir / "six.csv", "0 0 0 1 0 0\n");
  for (const char* f : {"short.csv", "words.csv", "bad_pose.csv", "six.csv", "p.xyz"}) {
    SCOPED_TRACE(f);
    try {
      if (std::string(f).find("pose") != std::string::npos || std::string(f) == "six.csv")
        io::read_pose_list(dir / f, Unit::Millimetre);
      else
        io::read_profiles(dir / f, {});
      FAIL() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
}
