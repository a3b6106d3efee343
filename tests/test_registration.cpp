// Registration: recovery of known poses on synthetic data, trust decisions, bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/registration/preprocess.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "laserfit/scan/reference.hpp"
#include "laserfit/scan/scanner.hpp"
#include "test_util.hpp"

using namespace laserfit;
namespace reg = laserfit::registration;

namespace {

TriMesh cad_mesh(const std::string& name) {
  return cad::import_cad(std::string(LASERFIT_SOURCE_DIR) + "/cad/" + name + ".ply").mesh;
}

PointCloud full_ref(const TriMesh& m, size_t n = 60000) {
  sampling::SamplingSettings s;
  s.count = n;
  s.seed = 11;
  return sampling::sample_uniform(m, s);
}

// What a noise-free scanner sees of `m` placed at T_scan_ref, viewed from `dir` (mesh frame);
// `viewpoint` receives the sensor position in the scan frame (normals are oriented towards it).
PointCloud scan_of(const TriMesh& m, const Pose& T_scan_ref, const Eigen::Vector3d& dir,
                   Eigen::Vector3d* viewpoint = nullptr, size_t n = 40000) {
  sampling::ViewSettings v;
  const Eigen::Vector3d c = m.bbox().center().cast<double>();
  v.T_mesh_sensor.push_back(look_at(c + dir.normalized() * 95, c));
  if (viewpoint) *viewpoint = T_scan_ref * v.T_mesh_sensor[0].translation();
  sampling::SamplingSettings s;
  s.count = n;
  s.seed = 99;  // a different sampling from the reference: no point coincides
  PointCloud scan = sampling::sample_visible(m, v, s);
  for (auto& p : scan.points) p = (T_scan_ref * p.cast<double>()).cast<float>();
  scan.normals.clear();
  return scan;
}

Pose test_pose() {
  return pose_from_tq({512.3, -40.7, 101.9}, Eigen::Quaterniond(Eigen::AngleAxisd(
                                                 0.35, Eigen::Vector3d(1, 2, 3).normalized())));
}

double trans_err_um(const Pose& a, const Pose& b) {
  return (a.translation() - b.translation()).norm() * 1e3;
}
double rot_err_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() * 180 / M_PI;
}

}  // namespace

TEST(Registration, RecoversAKnownPoseOfTheUsbPlug) {
  const TriMesh plug = cad_mesh("usb_a_plug");
  const Pose T = test_pose();
  Eigen::Vector3d viewpoint;
  const PointCloud scan = scan_of(plug, T, {0.3, -0.5, 1.0}, &viewpoint);
  for (const auto method : {reg::Refiner::Ceres, reg::Refiner::PointToPlane}) {
    SCOPED_TRACE(name_of(method));
    reg::RegistrationSettings s;
    s.refine.method = method;
    s.pre.use_viewpoint = true;
    s.pre.viewpoint = viewpoint;
    // The paper's orientation prior: q0 from the gripper, here 10 degrees off the truth.
    s.q0 = Eigen::Quaterniond(T.rotation() *
                              Eigen::AngleAxisd(0.17, Eigen::Vector3d::UnitX()).toRotationMatrix());
    const auto r = reg::register_cloud(scan, full_ref(plug), s);
    std::cout << name_of(method) << ": " << reg::status_name(r.status) << " " << r.reason
              << " t_err " << trans_err_um(r.T_scan_ref, T) << " um, r_err "
              << rot_err_deg(r.T_scan_ref, T) << " deg, rmse " << r.inlier_rmse_mm * 1e3
              << " um, overlap " << r.overlap << ", attempts " << r.attempts;
    for (const auto& [k, v] : r.timings_s) std::cout << " " << k << " " << v;
    std::cout << "\n";
    // Sub-micrometre: noise-free surface samples, scan points kept unaveraged (one real point per
    // voxel), exact CAD normals. Measured 0.50 um (ceres) and 0.94 um (point_to_plane).
    EXPECT_EQ(r.status, reg::Status::Ok) << r.reason;
    EXPECT_LT(trans_err_um(r.T_scan_ref, T), 1.0);
    EXPECT_LT(rot_err_deg(r.T_scan_ref, T), 0.01);
  }
}

namespace {
// A real simulated scan (every default noise source on) of one part placed at `T`, seen from
// 90 mm along `dir` (base frame), with the viewpoint for normal orientation.
struct Scanned {
  PointCloud cloud;
  Pose T_scan_object;
  Eigen::Vector3d viewpoint;
};
Scanned simulate(const TriMesh& m, const Pose& T, const Eigen::Vector3d& dir, uint64_t seed = 1) {
  scan::ScanScene sc;
  sc.seed = seed;
  sc.objects.push_back({"part", "", T, false, m});
  const Eigen::Vector3d c = T * m.bbox().center().cast<double>();
  auto& sw = sc.settings.sweep;
  sw.T_base_sensor_start = look_at(c + dir.normalized() * 90, c);
  sw.length_mm = 14, sw.speed_mm_s = 20, sw.profile_rate_hz = 1000;
  Pose back = Pose::Identity();
  back.translation() = Eigen::Vector3d(0, -7, 0);  // centre the sweep on the part
  sw.T_base_sensor_start = sw.T_base_sensor_start * back;
  const auto r = scan::simulate_scan(sc);
  return {r.cloud, r.T_scan_object[0], r.T_base_sensor_nominal[r.cloud.height / 2].translation()};
}

reg::RegistrationSettings settings_for(const Scanned& s, const Pose& truth) {
  reg::RegistrationSettings rs;
  rs.pre.use_viewpoint = true;
  rs.pre.viewpoint = s.viewpoint;
  rs.q0 = Eigen::Quaterniond(truth.rotation() *
                             Eigen::AngleAxisd(0.17, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  return rs;
}
}  // namespace

TEST(Registration, RecoversTheUsbPlugFromANoisyScan) {
  // Default sensor noise (1.5 um depth, speckle, dropouts, bias, arm errors) against the ground
  // truth T_scan_object.
  const TriMesh plug = cad_mesh("usb_a_plug");
  const Pose T = test_pose();
  // From the plug's front (its +z), tilted 25 degrees: the shell opening and the insulator are
  // what pins the plug along its length (the paper scans the plug from the front too).
  const Eigen::Vector3d front = T.rotation() * Eigen::Vector3d(0, -std::sin(0.44), std::cos(0.44));
  const auto scanned = simulate(plug, T, front);
  const auto r = reg::register_cloud(scanned.cloud, full_ref(plug),
                                     settings_for(scanned, scanned.T_scan_object));
  // Tolerance 20 um / 0.1 deg (measured 10.4 um, 0.016 deg); the success criterion is
  // 50 um / 0.5 deg. The campaign (make bench-registration) measures the distribution.
  EXPECT_EQ(r.status, reg::Status::Ok) << r.reason;
  EXPECT_LT(trans_err_um(r.T_scan_ref, scanned.T_scan_object), 20.0);
  EXPECT_LT(rot_err_deg(r.T_scan_ref, scanned.T_scan_object), 0.1);
  std::cout << "noisy scan: t_err " << trans_err_um(r.T_scan_ref, scanned.T_scan_object)
            << " um, r_err " << rot_err_deg(r.T_scan_ref, scanned.T_scan_object) << " deg, rmse "
            << r.inlier_rmse_mm * 1e3 << " um\n";
}

TEST(Registration, ADeclaredWeakDofIsAmbiguousUnlessClearlyPinned) {
  const TriMesh plug = cad_mesh("usb_a_plug");
  const Pose T = test_pose();
  const Eigen::Vector3d front = T.rotation() * Eigen::Vector3d(0, -std::sin(0.44), std::cos(0.44));
  const auto scanned = simulate(plug, T, front);
  auto rs = settings_for(scanned, scanned.T_scan_object);
  const auto r = reg::register_cloud(scanned.cloud, full_ref(plug), rs);
  ASSERT_EQ(r.status, reg::Status::Ok) << r.reason;
  // Declare the fit's weakest direction weak (in the plug's frame) with a ratio just above or
  // below the fit's own: ambiguous about exactly that direction, or still ok.
  const double ratio = r.hessian_eigenvalues[0] / r.hessian_eigenvalues[5];
  const Eigen::Matrix<double, 6, 1> d = r.weakest_direction;
  const bool rot = d.head<3>().norm() > d.tail<3>().norm();
  const Eigen::Vector3d axis =
      r.T_scan_ref.rotation().transpose() * (rot ? d.head<3>() : d.tail<3>()).normalized();
  (rot ? rs.trust.weak_rotation : rs.trust.weak_translation) = axis;
  rs.trust.declared_weak_ratio = 2 * ratio;
  const auto weak = reg::register_cloud(scanned.cloud, full_ref(plug), rs);
  ASSERT_EQ(weak.status, reg::Status::Ambiguous) << weak.reason;
  const Eigen::Vector3d in_scan = weak.T_scan_ref.rotation() * axis;
  EXPECT_TRUE(rot ? reg::weakest_is_rotation_about(weak, in_scan)
                  : reg::weakest_is_translation_along(weak, in_scan))
      << weak.reason;
  rs.trust.declared_weak_ratio = 0.5 * ratio;
  EXPECT_EQ(reg::register_cloud(scanned.cloud, full_ref(plug), rs).status, reg::Status::Ok);
}

TEST(Registration, RoundPegIsAmbiguousAboutItsAxis) {
  const TriMesh peg = cad_mesh("round_peg");
  const Pose T = test_pose();
  const auto scanned = simulate(peg, T, {1.0, 0.2, 0.3});
  auto rs = settings_for(scanned, scanned.T_scan_object);
  rs.q0.reset();  // the rho_rot gate is not symmetry-aware yet: RANSAC's roll is arbitrary here
  // PCL's point-to-plane ICP would abort on this singular system; it must be routed around it.
  rs.refine.method = reg::Refiner::PointToPlane;
  const auto r = reg::register_cloud(scanned.cloud, full_ref(peg), rs);
  ASSERT_EQ(r.status, reg::Status::Ambiguous) << r.reason;
  // The weakest direction is a rotation about the peg's axis (its z, in the scan frame).
  const Eigen::Vector3d axis = scanned.T_scan_object.rotation().col(2);
  EXPECT_GT(std::abs(r.weakest_direction.head<3>().normalized().dot(axis)), 0.99) << r.reason;
  // A side view of the peg's middle fixes the axis line, not the position along it: check the
  // translation error across the axis only (tolerance 50 um, the success criterion).
  const Eigen::Vector3d dt = r.T_scan_ref.translation() - scanned.T_scan_object.translation();
  EXPECT_LT((dt - dt.dot(axis) * axis).norm() * 1e3, 50.0);
}

TEST(Registration, WrongReferenceFails) {
  const auto scanned = simulate(cad_mesh("usb_a_plug"), test_pose(), {0.3, -0.5, 1.0});
  const auto r = reg::register_cloud(scanned.cloud, full_ref(cad_mesh("square_peg")),
                                     settings_for(scanned, scanned.T_scan_object));
  EXPECT_EQ(r.status, reg::Status::Failed) << r.reason;
}

TEST(Registration, SameSeedSamePoseWhateverTheThreadCount) {
  const TriMesh plug = cad_mesh("usb_a_plug");
  const auto scanned = simulate(plug, test_pose(), {0.3, -0.5, 1.0});
  const PointCloud ref = full_ref(plug);
  const auto s = settings_for(scanned, scanned.T_scan_object);
  const auto a = test::with_threads(1, [&] { return reg::register_cloud(scanned.cloud, ref, s); });
  const auto b = test::with_threads(2, [&] { return reg::register_cloud(scanned.cloud, ref, s); });
  EXPECT_EQ(a.T_scan_ref.matrix(), b.T_scan_ref.matrix());
}

TEST(Registration, SegmentationSeparatesPartsByTheirGap) {
  // A plug held 3 mm in front of a receptacle, scanned at 45 degrees with every noise source on:
  // one cluster holds the plug (>= 99 % of the points the simulator labelled plug, and almost
  // nothing else); no other cluster holds more than 1 % plug points. (The plate may split into
  // several clusters where the plug's shadow cuts it: that is fine.)
  scan::ScanScene sc;
  sc.objects.push_back({"receptacle", "", Pose::Identity(), false, cad_mesh("usb_a_receptacle")});
  sc.objects.push_back({"plug", "", pose_from_tq({0, 0, -3}, Eigen::Quaterniond::Identity()), false,
                        cad_mesh("usb_a_plug")});
  auto& sw = sc.settings.sweep;
  sw.T_base_sensor_start = look_at({0, -62, -62}, {0, 0, -4});
  sw.length_mm = 12, sw.speed_mm_s = 20, sw.profile_rate_hz = 500;
  const auto r = scan::simulate_scan(sc);
  const auto parts = reg::segment_clusters(r.cloud, 0.25, 0.75);
  size_t plug_total = 0;
  for (size_t i = 0; i < r.cloud.size(); ++i) plug_total += r.cloud.labels[i] == 1;
  ASSERT_GT(plug_total, 10000u);
  int plug_clusters = 0;
  for (const auto& p : parts) {
    const size_t plug = std::count(p.labels.begin(), p.labels.end(), 1);
    if (plug > 0.99 * p.size()) {
      ++plug_clusters;
      EXPECT_GT(plug, 0.99 * plug_total);
    } else {
      EXPECT_LT(plug, 0.01 * p.size());
    }
  }
  EXPECT_EQ(plug_clusters, 1);
}

TEST(Registration, RefusesUnusableInput) {
  const PointCloud ref = full_ref(cad_mesh("usb_a_plug"), 5000);
  PointCloud empty;
  EXPECT_THROW(reg::register_cloud(empty, ref, {}), Error);
  PointCloud nans;
  nans.points.assign(1000, Eigen::Vector3f::Constant(std::nanf("")));
  nans.width = 1000;
  EXPECT_THROW(reg::register_cloud(nans, ref, {}), Error);
  // Names are parsed once, at the edge, and every name of a table parses back to its value.
  EXPECT_THROW(parse_enum<reg::Method>("magic"), Error);
  for (const auto& n : names_of<reg::Method>()) EXPECT_EQ(name_of(parse_enum<reg::Method>(n)), n);
  for (const auto& n : names_of<reg::Refiner>()) EXPECT_EQ(name_of(parse_enum<reg::Refiner>(n)), n);
  // A method's settings say which method they are.
  for (const auto& n : names_of<reg::Method>()) {
    reg::RegistrationSettings s;
    reg::apply_method(s, parse_enum<reg::Method>(n));
    EXPECT_EQ(name_of(reg::method_of(s)), n);
  }
  // A weak DoF's axis is named x, y or z; anything else is an error, not an out-of-range index.
  EXPECT_EQ(*reg::named_axis("y"), Eigen::Vector3d::UnitY());
  EXPECT_FALSE(reg::named_axis(""));
  EXPECT_THROW(reg::named_axis("w"), Error);
  EXPECT_THROW(reg::named_axis("xy"), Error);
}

TEST(Registration, MixedPixelsAreRemovedFromOrganizedScans) {
  // Three profiles of a flat floor (12 um pitch); in the middle one, a point half-way up a
  // 2 mm depth jump (a mixed pixel) must go, and nothing else.
  const int W = 200;
  PointCloud c;
  c.width = W, c.height = 3;
  for (int r = 0; r < 3; ++r)
    for (int x = 0; x < W; ++x) c.points.emplace_back(0.012f * x, 0.01f * r, 0.0f);
  c.points[W + 100].z() = 1.0f;
  PointCloud unorganized = c;
  unorganized.width = 3 * W, unorganized.height = 1;
  EXPECT_EQ(reg::remove_mixed_pixels(c), 1u);
  EXPECT_FALSE(c.points[W + 100].allFinite());
  EXPECT_TRUE(c.points[W + 99].allFinite() && c.points[W + 101].allFinite());
  EXPECT_EQ(reg::remove_mixed_pixels(unorganized), 0u);  // no profile structure: left alone
}

TEST(Registration, CropNearThePriorKeepsOnlyPointsWithinTheRadius) {
  PointCloud ref;
  for (int i = 0; i <= 100; ++i) ref.points.emplace_back(0.04f * i, 0.0f, 0.0f);  // a 4 mm rod
  Pose prior = Pose::Identity();
  prior.translation() = Eigen::Vector3d(10, 0, 0);
  PointCloud scan;
  scan.points = {{11.0f, 0.5f, 0.0f},
                 {12.0f, 0.0f, 0.99f},
                 {11.0f, 0.0f, 1.01f},
                 {20.0f, 0.0f, 0.0f},
                 {9.5f, 0.0f, 0.0f}};
  scan.width = 5;
  const PointCloud near = reg::crop_near(scan, ref, prior, 1.0);
  ASSERT_EQ(near.points.size(), 3u);  // within 1 mm of the rod placed at x = 10..14
  EXPECT_FLOAT_EQ(near.points[0].y(), 0.5f);
  EXPECT_FLOAT_EQ(near.points[1].z(), 0.99f);
  EXPECT_FLOAT_EQ(near.points[2].x(), 9.5f);
}

TEST(Registration, APartCutInTwoByAShadowIsPinnedByBothPieces) {
  // The needle seen from above its eye (noise-free), only its first 12 mm (the scanner's window),
  // with a 0.3 mm strip across the shaft between the head and the eye missing — the thread's
  // shadow. The largest cluster (eye and shaft) alone slides along the shaft (the eye's rims are
  // seen face-on): a RANSAC restart lands 5 mm along it with a marginally lower fitness, and
  // the attempt nearest to the prior must be kept; then the head piece beyond the gap pins it.
  // Tolerance: 10 um along and across the shaft, only the spin about it left unobservable.
  const TriMesh needle = cad_mesh("needle");
  const Pose T = test_pose();
  sampling::ViewSettings v;  // looking at the eye end from 95 mm
  const Eigen::Vector3d c(5, 0, 0);
  v.T_mesh_sensor.push_back(look_at(c + Eigen::Vector3d(0.1, 0.2, 1.0).normalized() * 95, c));
  sampling::SamplingSettings ss;
  ss.count = 40000, ss.seed = 99;
  const PointCloud seen = sampling::sample_visible(needle, v, ss);
  PointCloud scan;
  for (const auto& p : seen.points) {
    const double x = p.x();  // along the needle, head at -1
    if (x < 12 && (x < -0.7 || x > -0.4))
      scan.points.push_back((T * p.cast<double>()).cast<float>());
  }
  const Eigen::Vector3d vp = T * v.T_mesh_sensor[0].translation();
  scan.width = int(scan.points.size());
  reg::RegistrationSettings rs;
  rs.pre.use_viewpoint = true, rs.pre.viewpoint = vp;
  rs.pre.voxel_mm = 0.03;  // the needle's tuned voxel: the strip is 10 voxels wide
  // The arm's prior 0.7 mm off along the shaft: the points within 0.3 mm of the reference placed
  // there miss the head piece, and so does the cluster nearest to it.
  rs.prior =
      T * pose_from_tq({0.7, 0.1, 0},
                       Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY())));
  rs.q0 = Eigen::Quaterniond(rs.prior->rotation());
  rs.prior_radius_mm = 0.3;
  const auto parts = reg::segment_clusters(scan, rs.pre.voxel_mm, 3 * rs.pre.voxel_mm, 20);
  ASSERT_GE(parts.size(), 2u);  // the strip separates the head from the shaft
  int cluster = -1;
  const auto r =
      reg::register_segmented(scan, full_ref(needle), rs, 1, &cluster);  // near the prior only
  ASSERT_NE(r.status, reg::Status::Failed) << r.reason;
  EXPECT_LE(r.unobservable, 1) << r.reason;
  EXPECT_EQ(cluster, reg::kRegrownPart);  // the regrown candidate won
  const Eigen::Vector3d axis = T.rotation().col(0);
  const Eigen::Vector3d dt = r.T_scan_ref.translation() - T.translation();
  EXPECT_LT(std::abs(dt.dot(axis)) * 1e3, 10.0);
  EXPECT_LT((dt - dt.dot(axis) * axis).norm() * 1e3, 10.0);
}
