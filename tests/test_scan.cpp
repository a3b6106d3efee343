// Laser line-scanner simulator: geometry exact without noise, noise statistics as configured,
// step heights, shadows where the geometry puts them, determinism, ground truth, bad scenes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <unordered_set>

#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/mesh_writer.hpp"
#include "laserfit/raycast/scene.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "laserfit/scan/scanner.hpp"
#include "laserfit/sensor/assemble.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {

// A 60 x 60 mm plate with its top at z = 0 and, optionally, a 2 mm step block on it; the scanner
// 90 mm above looking down, laser line along x, sweeping 10 mm along base y across the block edge.
scan::ScanScene step_scene(double step_mm, bool noise) {
  scan::ScanScene sc;
  sc.objects.push_back(
      {"plate", "", Pose::Identity(), false, test::box_mesh({-30, -30, -5}, {30, 30, 0})});
  if (step_mm > 0)
    sc.objects.push_back({"block", "", Pose::Identity(), false,
                          test::box_mesh({-5, 0, 0}, {5, 20, float(step_mm)})});
  auto& s = sc.settings;
  s.sweep.T_base_sensor_start = look_at({0, -5, 90}, {0, -5, 0});
  s.sweep.direction = {0, -1, 0};  // sensor y = base -y here; move along base +y
  s.sweep.length_mm = 10;
  s.sweep.profile_rate_hz = 200;  // 50 um between profiles: fast tests
  s.noise.enabled = s.motion.enabled = noise;
  return sc;
}

// Least-squares plane z = a + b x + c y through points.
Eigen::Vector3d fit_plane(const std::vector<Eigen::Vector3d>& p) {
  Eigen::MatrixXd A(p.size(), 3);
  Eigen::VectorXd z(p.size());
  for (size_t i = 0; i < p.size(); ++i) A.row(i) << 1, p[i].x(), p[i].y(), z(i) = p[i].z();
  return A.colPivHouseholderQr().solve(z);
}

std::vector<Eigen::Vector3d> valid_points(const PointCloud& c, int label) {
  std::vector<Eigen::Vector3d> out;
  for (size_t i = 0; i < c.size(); ++i)
    if (c.points[i].allFinite() && (label < 0 || c.labels[i] == label))
      out.push_back(c.points[i].cast<double>());
  return out;
}

}  // namespace

TEST(Scan, ProfilesHave2048PointsAndNoNoiseMeansExactGeometry) {
  const auto r = scan::simulate_scan(step_scene(0, false));
  EXPECT_EQ(r.cloud.width, 2048);
  EXPECT_EQ(r.cloud.height, 201);  // 10 mm at 50 um + the first profile
  EXPECT_EQ(r.cloud.size(), 2048u * 201u);
  const auto pts = valid_points(r.cloud, -1);
  EXPECT_GT(pts.size(), 0.99 * r.cloud.size());
  // Tolerance 2e-5 mm: Embree returns the ray distance (~90 mm) as a float, ulp 7.6e-6 mm.
  for (const auto& p : pts) ASSERT_LT(std::abs(p.z()), 2e-5) << p.transpose();
  // The profile spans the 25 mm line width at 90 mm (mid range): pitch ~12.2 um.
  double xmin = 1e9, xmax = -1e9;
  for (int j = 0; j < 2048; ++j) {
    const auto& p = r.cloud.points[j];
    if (p.allFinite()) xmin = std::min(xmin, double(p.x())), xmax = std::max(xmax, double(p.x()));
  }
  EXPECT_NEAR(xmax - xmin, 25.0, 0.01);
}

TEST(Scan, DepthNoiseHasTheConfiguredSigma) {
  for (double sigma_um : {1.5, 5.0}) {
    auto sc = step_scene(0, true);
    auto& n = sc.settings.noise;
    n = scan::NoiseSettings{};
    n.depth_sigma_um = sigma_um;
    n.x_jitter_um = n.speckle_sigma_um = n.dropout_rate = n.mixed_pixel_prob = n.bias_sigma_um = 0;
    n.z_quantum_um = 0;
    sc.settings.motion.enabled = false;
    const auto pts = valid_points(scan::simulate_scan(sc).cloud, -1);
    double ss = 0;
    for (const auto& p : pts) ss += p.z() * p.z();
    // Noise is along the laser ray with sigma / cos(incidence); on a plane facing the sensor its
    // z component has exactly sigma. Tolerance: 10 % (the issue's), sampling error here ~0.2 %.
    const double measured = std::sqrt(ss / pts.size()) * 1e3;
    std::cout << "depth noise: configured " << sigma_um << " um, measured " << measured
              << " um over " << pts.size() << " points\n";
    EXPECT_NEAR(measured, sigma_um, 0.1 * sigma_um);
  }
}

TEST(Scan, StepHeightMeasuredWithin2um) {
  const double h = 2.0;
  const auto r = scan::simulate_scan(step_scene(h, true));  // every default noise source on
  std::vector<Eigen::Vector3d> low, high;
  for (const auto& p : valid_points(r.cloud, -1)) {
    if (std::abs(p.x()) > 6.0 && std::abs(p.x()) < 11.0 && p.y() > 1.0 && p.y() < 4.5)
      low.push_back(p);
    if (std::abs(p.x()) < 4.0 && p.y() > 1.0 && p.y() < 4.5) high.push_back(p);
  }
  ASSERT_GT(low.size(), 10000u);
  ASSERT_GT(high.size(), 10000u);
  const Eigen::Vector3d plane = fit_plane(low);
  double sum = 0;
  for (const auto& p : high) sum += p.z() - (plane(0) + plane(1) * p.x() + plane(2) * p.y());
  std::cout << "step: true " << h << " mm, measured " << sum / high.size() << " mm ("
            << (sum / high.size() - h) * 1e3 << " um) from " << low.size() << " + " << high.size()
            << " points\n";
  EXPECT_NEAR(sum / high.size(), h, 2e-3);
}

TEST(Scan, CameraShadowFallsOnTheSideAwayFromTheCamera) {
  // The block's edge at base y = 0 faces -y. With the camera on the -y side (sensor y = base -y)
  // the plate right in front of the edge is seen; turn the sensor 180 degrees about the vertical
  // (camera on the +y side, looking over the 2 mm block) and a band of width
  // 2 mm x baseline / 90 mm (~0.93 mm) in front of the edge falls into the camera's shadow.
  for (const bool camera_over_block : {false, true}) {
    SCOPED_TRACE(camera_over_block);
    auto sc = step_scene(2.0, false);
    if (camera_over_block) {
      sc.settings.sweep.T_base_sensor_start =
          look_at({0, -5, 90}, {0, -5, 0}, -Eigen::Vector3d::UnitX());
      sc.settings.sweep.direction = {0, 1, 0};  // sensor y = base +y now
    }
    const auto r = scan::simulate_scan(sc);
    const double shadow = 2.0 * sc.settings.sensor.baseline_mm() / 90.0;
    size_t band = 0;
    for (const auto& p : valid_points(r.cloud, 0))  // plate points just in front of the edge
      if (std::abs(p.x()) < 4.0 && p.y() < -0.05 && p.y() > -shadow + 0.05) ++band;
    if (camera_over_block)
      EXPECT_EQ(band, 0u) << "the block hides the plate in front of its edge from the camera";
    else
      EXPECT_GT(band, 1000u) << "a camera on the near side sees the plate up to the edge";
  }
}

TEST(Scan, SameSeedSameBytesWhateverTheThreadCount) {
  test::TempDir dir;
  const auto sc = step_scene(2.0, true);
  io::write_cloud(dir / "one.pcd",
                  test::with_threads(1, [&] { return scan::simulate_scan(sc).cloud; }));
  io::write_cloud(dir / "two.pcd",
                  test::with_threads(2, [&] { return scan::simulate_scan(sc).cloud; }));
  auto other = sc;
  other.seed = 2;
  io::write_cloud(dir / "three.pcd", scan::simulate_scan(other).cloud);
  EXPECT_TRUE(test::read_bytes(dir / "one.pcd") == test::read_bytes(dir / "two.pcd"));
  EXPECT_FALSE(test::read_bytes(dir / "one.pcd") == test::read_bytes(dir / "three.pcd"));
}

TEST(Scan, GroundTruthExplainsTheScanUnderArmErrors) {
  // A rigid arm error and a translational calibration error, no sensor noise: every plate point
  // mapped through the ground-truth T_scan_object lands on the plate's top face (z = 0) within
  // 1e-4 mm, while the nominal (identity) pose is off by the errors.
  auto sc = step_scene(0, false);
  auto& m = sc.settings.motion;
  m.enabled = true;
  m.offset_sigma_mm = 0.5, m.offset_sigma_deg = 0.5;
  m.jitter_sigma_mm = m.jitter_sigma_deg = 0;
  m.calibration_error = {0.3, -0.2, 0.5, 0, 0, 0};
  auto residual = [](const scan::ScanResult& r) {
    const Pose inv = r.T_scan_object[0].inverse();
    double worst = 0;
    for (const auto& p : valid_points(r.cloud, 0)) worst = std::max(worst, std::abs((inv * p).z()));
    return worst;
  };
  const auto r = scan::simulate_scan(sc);
  EXPECT_LT(residual(r), 1e-4);
  double nominal = 0;
  for (const auto& p : valid_points(r.cloud, 0)) nominal = std::max(nominal, std::abs(p.z()));
  EXPECT_GT(nominal, 0.05);
  // A rotational calibration error is not rigid: the sweep runs along the nominal axis while the
  // laser plane is tilted, which shears the cloud by about sweep length x angle (10 mm x 0.2 deg).
  m.calibration_error = {0, 0, 0, 0.2, 0, 0};
  const double shear = residual(scan::simulate_scan(sc)), expected = 10.0 * 0.2 * M_PI / 180;
  EXPECT_GT(shear, 0.25 * expected);
  EXPECT_LT(shear, 2.0 * expected);
}

// Embree's 8- and 16-wide packet kernels must agree: which one runs depends on the CPU, the
// scans must not. A fan across the step scene's block (edges, faces at all heights) and shadow
// segments towards a low camera, which the block hides part of the plate from. Tolerance: exact
// (same triangle, same distance, same visibility).
TEST(Scan, PacketWidthChangesNoHit) {
  const auto sc = step_scene(10, false);
  raycast::Scene s8(raycast::PacketWidth::w8), s16(raycast::PacketWidth::w16);
  for (auto* s : {&s8, &s16}) {
    for (const auto& o : sc.objects) s->add_mesh(o.mesh, o.T_base_object);
    s->commit();
  }
  const Eigen::Vector3f origin(0.3f, 3.0f, 60.0f), camera(0.0f, 40.0f, 5.0f);
  std::vector<Eigen::Vector3f> dirs;
  for (int i = 0; i < 2047; ++i)  // not a multiple of a packet: the last one is partial
    dirs.push_back(Eigen::Vector3f(-0.6f + 1.2f * i / 2046, 0.01f * (i % 7), -1.0f).normalized());
  std::vector<raycast::Hit> h8, h16;
  s8.intersect_fan(origin, dirs, 0.f, 200.f, h8);
  s16.intersect_fan(origin, dirs, 0.f, 200.f, h16);
  std::vector<Eigen::Vector3f> from(dirs.size()), to(dirs.size(), camera);
  std::vector<uint8_t> active(dirs.size(), 0);
  for (size_t i = 0; i < dirs.size(); ++i) {
    ASSERT_EQ(h8[i].geom, h16[i].geom) << i;
    ASSERT_EQ(h8[i].prim, h16[i].prim) << i;
    if (!h8[i].valid()) continue;
    ASSERT_EQ(h8[i].t, h16[i].t) << i;
    from[i] = origin + h8[i].t * dirs[i] + 0.001f * h8[i].normal, active[i] = 1;
  }
  std::vector<uint8_t> c8(dirs.size(), 7), c16(dirs.size(), 7);
  s8.segments_clear(from, to, active, 0.001f, c8);
  s16.segments_clear(from, to, active, 0.001f, c16);
  EXPECT_EQ(c8, c16);
  // The case is what it claims: misses beyond the plate, hits on both objects, hidden points.
  EXPECT_GT(std::count(active.begin(), active.end(), 0), 100);
  EXPECT_GT(std::count_if(h8.begin(), h8.end(), [](const auto& h) { return h.geom == 1; }), 100);
  EXPECT_GT(std::count(c8.begin(), c8.end(), 0), 10);
}

TEST(Scan, MatchesTheViewDependentReferenceCloud) {
  // One mechanism: the noise-free scan of a part and its view-dependent reference cloud from the
  // same sweep must cover the same surface. Tolerance: voxels of 0.06 mm (5 line pitches), 99 %.
  const std::string plug = std::string(LASERFIT_SOURCE_DIR) + "/cad/usb_a_plug.ply";
  scan::ScanScene sc;
  sc.objects.push_back({"plug", plug, Pose::Identity(), false, cad::import_cad(plug).mesh});
  auto& sw = sc.settings.sweep;
  sw.T_base_sensor_start = look_at({0, 6, 90}, {0, 6, 0});           // sensor y = base -y
  sw.length_mm = 12, sw.speed_mm_s = 20, sw.profile_rate_hz = 1000;  // 20 um profiles
  sc.settings.noise.enabled = sc.settings.motion.enabled = false;
  const auto scan_pts = valid_points(scan::simulate_scan(sc).cloud, -1);

  sampling::ViewSettings v;
  v.T_mesh_sensor = {sw.T_base_sensor_start};
  sampling::SamplingSettings s;
  s.density_per_mm2 = 2000;
  const PointCloud ref = sampling::sample_visible(sc.objects[0].mesh, v, s);
  const Pose to_sensor = sw.T_base_sensor_start.inverse();
  std::vector<Eigen::Vector3d> ref_in_sweep;  // the refcloud sees the whole swept strip
  for (const auto& p : ref.points) {
    const double y = (to_sensor * p.cast<double>()).y();
    if (y > 0.1 && y < sw.length_mm - 0.1) ref_in_sweep.push_back(p.cast<double>());
  }
  ASSERT_GT(scan_pts.size(), 50000u);
  ASSERT_GT(ref_in_sweep.size(), 50000u);

  const double voxel = 0.06;
  auto key = [&](const Eigen::Vector3d& p, int dx, int dy, int dz) {
    const Eigen::Vector3i c = (p / voxel).array().floor().cast<int>() + Eigen::Array3i(dx, dy, dz);
    return (int64_t(c.x()) * 73856093) ^ (int64_t(c.y()) * 19349663) ^ (int64_t(c.z()) * 83492791);
  };
  auto covered = [&](const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
    std::unordered_set<int64_t> grid;
    for (const auto& p : b) grid.insert(key(p, 0, 0, 0));
    size_t hit = 0;
    for (const auto& p : a) {
      bool found = false;
      for (int dx = -1; dx <= 1 && !found; ++dx)
        for (int dy = -1; dy <= 1 && !found; ++dy)
          for (int dz = -1; dz <= 1 && !found; ++dz) found = grid.count(key(p, dx, dy, dz)) > 0;
      hit += found;
    }
    return double(hit) / a.size();
  };
  EXPECT_GT(covered(scan_pts, ref_in_sweep), 0.99) << "scan points off the reference cloud";
  EXPECT_GT(covered(ref_in_sweep, scan_pts), 0.99) << "reference points the scanner never saw";
}

TEST(Scan, BadScenesAreRefusedNamingTheFile) {
  test::TempDir dir;
  io::write_mesh(dir / "box.ply", test::box_mesh({0, 0, 0}, {10, 10, 10}));
  const std::string ok_sweep = "sweep: {start: [5, 5, 95, 0, 1, 0, 0], length_mm: 2}\n";
  const std::string obj = "objects: [{name: b, mesh: box.ply, pose: [0, 0, 0, 1, 0, 0, 0]}]\n";
  test::write_text(dir / "good.yaml", obj + ok_sweep);
  EXPECT_GT(scan::simulate_scan(scan::load_scene(dir / "good.yaml")).stats.valid, 0u);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"unknown_mesh.yaml",
       "objects: [{mesh: nope.ply, pose: [0, 0, 0, 1, 0, 0, 0]}]\n" + ok_sweep},
      {"bad_pose.yaml", "objects: [{mesh: box.ply, pose: [0, 0, 0, 2, 0, 0, 0]}]\n" + ok_sweep},
      {"short_pose.yaml", "objects: [{mesh: box.ply, pose: [0, 0, 0]}]\n" + ok_sweep},
      {"negative_speed.yaml", obj + "sweep: {start: [5, 5, 95, 0, 1, 0, 0], speed_mm_s: -1}\n"},
      {"typo.yaml", obj + ok_sweep + "noise: {depth_sigma: 1.5}\n"},
      {"no_sweep.yaml", obj},
      {"not_yaml.yaml", "objects: [unclosed\n"},
      {"empty.yaml", ""},
      {"range.yaml", obj + ok_sweep + "sensor: {z_min_mm: 100, z_max_mm: 90}\n"},
  };
  for (const auto& [name, text] : bad) {
    SCOPED_TRACE(name);
    test::write_text(dir / name, text);
    try {
      scan::simulate_scan(scan::load_scene(dir / name));
      FAIL() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

// laserfit assemble's round trip: the raw profiles of a scan (`laserfit scan --raw`, sensor frame),
// the flange poses that put the scanner where the scan had it (through a hand-eye pose that is
// not the identity) and that hand-eye give back the scan's cloud: same grid, same missing points,
// every point within one float rounding at 100 mm (0.01 um; the scan composes from unrounded
// profile values, the assembly from the file's floats).
TEST(Scan, AssembledFromRawProfilesAndFlangePosesItIsTheScan) {
  const auto r = scan::simulate_scan(step_scene(2, true));
  const Pose T_flange_sensor = pose_from_tq(
      {10, -20, 80},
      Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 2, 3).normalized())));
  std::vector<Pose> T_base_flange;
  for (const Pose& T_base_sensor : r.T_base_sensor_nominal)
    T_base_flange.push_back(T_base_sensor * T_flange_sensor.inverse());
  io::Profiles p;
  p.width = r.raw.width, p.count = r.raw.height;
  for (const auto& q : r.raw.points) p.xz.emplace_back(q.x(), q.z());
  const PointCloud c = sensor::assemble_scan(p, T_base_flange, T_flange_sensor);
  ASSERT_EQ(c.width, r.cloud.width);
  ASSERT_EQ(c.height, r.cloud.height);
  size_t measured = 0;
  for (size_t k = 0; k < c.size(); ++k) {
    ASSERT_EQ(c.points[k].allFinite(), r.cloud.points[k].allFinite()) << k;
    if (!c.points[k].allFinite()) continue;
    ++measured;
    EXPECT_LE((c.points[k] - r.cloud.points[k]).norm(), 1e-5) << k;
  }
  EXPECT_GT(measured, c.size() / 2);
  ASSERT_TRUE(c.sensor_origin);
  EXPECT_LE((*c.sensor_origin - *r.cloud.sensor_origin).norm(), 1e-9);
  T_base_flange.pop_back();
  EXPECT_THROW(sensor::assemble_scan(p, T_base_flange, T_flange_sensor), Error);
}
