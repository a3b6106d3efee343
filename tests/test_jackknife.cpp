// The block-jackknife trust test: a pose that one small region of the scan pins, where that
// region's points are biased (as mixed pixels bias an edge), is reported `ambiguous` although its
// Hessian is well conditioned; the same scan without the bias is `ok`.
#include <gtest/gtest.h>

#include <random>

#include "laserfit/registration/registration.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "test_util.hpp"

using namespace laserfit;
namespace reg = laserfit::registration;

namespace {

// A 40 x 30 mm plate with two 8 mm square bosses, 2 mm high, near opposite corners, 50 mm from the
// mesh origin (as a panel's scan window sees a corner of it, far from the part's frame).
TriMesh plate_with_bosses() {
  TriMesh m;
  auto add = [&m](const TriMesh& b) {
    const int base = int(m.vertices.size());
    m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (const auto& f : b.faces) m.faces.emplace_back(f.x() + base, f.y() + base, f.z() + base);
  };
  add(test::box_mesh({30, -15, -2}, {70, 15, 0}));
  // Frusta with 45 deg sides (a box whose top face is shrunk): a line scanner sees all four
  // sides from above, so each boss alone pins both in-plane directions.
  auto frustum = [](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
    TriMesh b = test::box_mesh(lo, hi);
    const float inset = hi.z() - lo.z();
    const Eigen::Vector3f c = b.bbox().center();
    for (auto& v : b.vertices)
      if (v.z() == hi.z())
        v.head<2>() = c.head<2>() + (v - c).head<2>().cwiseSign() * ((hi - lo).x() / 2 - inset);
    return b;
  };
  add(frustum({33, -13, 0}, {41, -5, 2}));
  add(frustum({59, 5, 0}, {67, 13, 2}));
  return m;
}

struct Case {
  PointCloud scan;
  Eigen::Vector3d viewpoint;
};

// A line scanner 95 mm above the plate's centre, tilted ~13 deg.
sampling::ViewSettings view() {
  sampling::ViewSettings v;
  const Eigen::Vector3d c(50, 0, 0);
  v.T_mesh_sensor.push_back(look_at(c + Eigen::Vector3d(0.2, 0.1, 1).normalized() * 95, c));
  return v;
}

// What that scanner sees of the plate at T, cropped to a window inside the plate's outline (its
// edges would pin the pose on their own), with 1 um white depth noise; the points of the first
// boss (x < 42, y < -4 in the mesh frame) move by `bias` (mm) along x.
Case scan_plate(const TriMesh& m, const Pose& T, double bias) {
  const sampling::ViewSettings v = view();
  sampling::SamplingSettings s;
  s.count = 40000;
  s.seed = 99;
  const PointCloud seen = sampling::sample_visible(m, v, s);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0, 1e-3);
  Case out;
  out.viewpoint = T * v.T_mesh_sensor[0].translation();
  for (const auto& p : seen.points) {
    if (p.x() < 32 || p.x() > 68 || p.y() < -13.5 || p.y() > 13.5 || p.z() < -0.01) continue;
    Eigen::Vector3d q = p.cast<double>();
    if (q.x() < 42 && q.y() < -4) q.x() += bias;
    q.z() += noise(rng);
    out.scan.points.push_back((T * q).cast<float>());
  }
  return out;
}

reg::RegistrationResult run(const TriMesh& m, const Pose& T, double bias) {
  const Case c = scan_plate(m, T, bias);
  sampling::SamplingSettings s;  // the view-dependent reference, denser than the scan
  s.count = 150000;
  s.seed = 11;
  reg::RegistrationSettings rs;
  rs.pre.use_viewpoint = true;
  rs.pre.viewpoint = c.viewpoint;
  rs.pre.voxel_mm = 0.1;
  rs.prior = T;
  rs.skip_coarse = true;
  rs.trust.max_sigma_mm = 0.005;
  return reg::register_cloud(c.scan, sampling::sample_visible(m, view(), s), rs);
}

}  // namespace

TEST(Jackknife, ABiasedRegionThatAlonePinsThePoseIsNotTrusted) {
  const TriMesh m = plate_with_bosses();
  const Pose T = pose_from_tq({400, -30, 5},
                              Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())));
  const auto clean = run(m, T, 0);
  const auto biased = run(m, T, 0.03);  // one boss seen 30 um off along x
  auto t_err_um = [&](const reg::RegistrationResult& r) {
    return (r.T_scan_ref.translation() - T.translation()).norm() * 1e3;
  };
  const Eigen::Vector3d window = T * Eigen::Vector3d(50, 0, 0);  // ~ the matched points' centroid
  // The origin's sigma from sigma^2 H^-1 (independent residuals), for comparison.
  auto covariance_sigma_um = [&](const reg::RegistrationResult& r) {
    return reg::origin_sigma_mm(r.covariance, r.T_scan_ref.translation() - window) * 1e3;
  };
  std::cout << "clean: " << reg::status_name(clean.status) << ", jackknife sigma "
            << clean.sigma_origin_mm * 1e3 << " um, t_err " << t_err_um(clean)
            << " um; biased: " << reg::status_name(biased.status) << ", jackknife sigma "
            << biased.sigma_origin_mm * 1e3 << " um, sigma from H^-1 "
            << covariance_sigma_um(biased) << " um, t_err " << t_err_um(biased) << " um ("
            << biased.reason << ")\n";
  // Clean (1 um white noise): ok, sigma and error under 1 um (measured 0.17 and 0.12 um).
  EXPECT_EQ(clean.status, reg::Status::Ok) << clean.reason;
  EXPECT_LT(clean.sigma_origin_mm * 1e3, 1.0);
  EXPECT_LT(t_err_um(clean), 1.0);
  // Biased: the origin is off by ~30 um (measured 31.6). The jackknife sees a third of it
  // (measured 9.6 um, checked > 1/4 of the error); sigma^2 H^-1 sees almost nothing (checked
  // < 1/10 of the jackknife's). Over the 5 um limit set above: ambiguous.
  EXPECT_GT(t_err_um(biased), 20.0);
  EXPECT_GT(biased.sigma_origin_mm * 1e3, t_err_um(biased) / 4);
  EXPECT_LT(covariance_sigma_um(biased), biased.sigma_origin_mm * 1e3 / 10);
  EXPECT_EQ(biased.status, reg::Status::Ambiguous) << biased.reason;
  EXPECT_NE(biased.reason.find("not pinned"), std::string::npos) << biased.reason;
}
