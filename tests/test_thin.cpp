// The thin-part detector (registration/thin.hpp): the 150 um thread of the needle scene, seen
// with every default noise source, from a prior millimetres off.
#include <gtest/gtest.h>

#include <cmath>

#include "laserfit/core/error.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/scan/reference.hpp"
#include "laserfit/scan/scanner.hpp"

using namespace laserfit;
namespace reg = laserfit::registration;

namespace {

struct ThreadScene {
  scan::ScanScene scene;
  scan::ScanResult scan;
  PointCloud ref;  // what the sweep sees of the thread, in its own frame
  Pose truth;      // T_scan_thread
  Eigen::Vector3d viewpoint;
};

const ThreadScene& thread_scene() {
  static const ThreadScene t = [] {
    ThreadScene s;
    s.scene =
        scan::load_scene(std::string(LASERFIT_SOURCE_DIR) + "/datasets/scenes/needle_thread.yaml");
    s.scan = scan::simulate_scan(s.scene);
    const auto& thread = s.scene.objects.at(1);
    s.ref = scan::view_reference(thread.mesh, thread.T_base_object, s.scene.settings, 20000, 3);
    s.truth = s.scan.T_scan_object.at(1);
    s.viewpoint = scan::mid_sweep(s.scene.settings).translation();
    return s;
  }();
  return t;
}

// A prior as an arm would give it: 0.8 mm and 4 degrees off.
reg::RegistrationSettings settings_with_prior(const ThreadScene& t) {
  reg::RegistrationSettings s;
  s.pre.use_viewpoint = true;
  s.pre.viewpoint = t.viewpoint;
  Pose prior =
      t.truth * Pose(Eigen::AngleAxisd(4 * M_PI / 180, Eigen::Vector3d(1, 1, 0).normalized()));
  prior.translation() += Eigen::Vector3d(0.5, -0.4, 0.5);
  s.prior = prior;
  return s;
}

}  // namespace

TEST(ThinPart, ProfileOfTheThreadReference) {
  // The view reference holds only the side the sweep sees; the circle fit must still give the
  // modelled radius (75 um; tolerance 3 um) and call the thread thin, the needle not.
  const auto& t = thread_scene();
  const auto p = reg::thin_profile(t.ref, {});
  EXPECT_TRUE(p.thin);
  EXPECT_NEAR(p.radius_mm, 0.075, 0.003);
  EXPECT_NEAR(p.tip.head<2>().norm(), 0.0, 0.003);  // the tip is on the thread's z axis
  // The cut end faces away from the sweep and the last few tens of um of the side graze the
  // laser: the seen tip is up to 60 um behind the modelled one (measured 40 um).
  EXPECT_NEAR(p.tip.z(), -0.03, 0.03);
  const auto& needle = t.scene.objects.at(0);
  const PointCloud nref =
      scan::view_reference(needle.mesh, needle.T_base_object, t.scene.settings, 20000, 3);
  EXPECT_FALSE(reg::thin_profile(nref, {}).thin);
}

TEST(ThinPart, DetectsTheThreadTipFromAPriorMillimetresOff) {
  const auto& t = thread_scene();
  const auto r = reg::register_cloud(t.scan.cloud, t.ref, settings_with_prior(t));
  ASSERT_EQ(r.status, reg::Status::Ambiguous) << r.reason;
  ASSERT_EQ(r.unobservable, 1);
  const Eigen::Vector3d axis = t.truth.rotation().col(2);
  // The unobservable direction is the spin about the thread's own axis.
  EXPECT_GT(std::abs(r.weakest_direction.head<3>().normalized().dot(axis)), 0.999);
  // Axis within 1 degree; the tip across the axis within 10 um (what the eye's +-75 um clearance
  // needs; measured 1.9 um), along it within 40 um (measured 14 um short: the tip ends between
  // two profiles, ~40 um apart along the thread, and its last tens of um graze the laser).
  EXPECT_LT(std::acos(std::min(1.0, r.T_scan_ref.rotation().col(2).dot(axis))) * 180 / M_PI, 1.0);
  const Eigen::Vector3d dt = r.T_scan_ref.translation() - t.truth.translation();
  std::cout << "thread tip: across " << (dt - dt.dot(axis) * axis).norm() * 1e3 << " um, along "
            << dt.dot(axis) * 1e3 << " um; " << r.reason << "\n";
  EXPECT_LT((dt - dt.dot(axis) * axis).norm() * 1e3, 10.0);
  EXPECT_LT(std::abs(dt.dot(axis)) * 1e3, 40.0);
  // register_segmented takes the same route (a thin part is segmented by the detector itself).
  const auto seg = reg::register_segmented(t.scan.cloud, t.ref, settings_with_prior(t));
  EXPECT_EQ(seg.T_scan_ref.matrix(), r.T_scan_ref.matrix());
}

// The thread tilted 9 deg further toward the sensor (24 deg from the view axis: the needle
// suite's trial 3, whose pose this is). Each profile then paints ~0.3 mm of its length, and the
// sweep sees ~1000 points of it. The line test must not depend on that density: with the raw
// points and a cap of 48 on their number, the nearest points spanned a patch of the band as wide
// as it is long and none counted as a line. Tolerances as above.
TEST(ThinPart, DetectsADenselySeenThread) {
  ThreadScene t = thread_scene();
  t.scene.objects.at(1).T_base_object =
      Eigen::Translation3d(451.252, 100.082, 252.858) *
      Eigen::Quaterniond(0.0811, 0.9937, -0.0764, 0.0105).normalized();
  t.scan = scan::simulate_scan(t.scene);
  t.truth = t.scan.T_scan_object.at(1);
  long on_thread = 0;
  for (size_t i = 0; i < t.scan.cloud.labels.size(); ++i)
    on_thread += t.scan.cloud.labels[i] == 1 && t.scan.cloud.points[i].allFinite();
  ASSERT_GT(on_thread, 700);
  const auto r = reg::register_cloud(t.scan.cloud, t.ref, settings_with_prior(t));
  ASSERT_EQ(r.status, reg::Status::Ambiguous) << r.reason;
  const Eigen::Vector3d axis = t.truth.rotation().col(2);
  const Eigen::Vector3d dt = r.T_scan_ref.translation() - t.truth.translation();
  std::cout << "dense thread (" << on_thread << " points): across "
            << (dt - dt.dot(axis) * axis).norm() * 1e3 << " um, along " << dt.dot(axis) * 1e3
            << " um\n";
  EXPECT_LT((dt - dt.dot(axis) * axis).norm() * 1e3, 10.0);
  EXPECT_LT(std::abs(dt.dot(axis)) * 1e3, 40.0);
}

// Two stray points on the cylinder's band 0.1 and 0.2 mm past the tip (as mixed pixels between
// the thread's end and the needle under it leave them) do not move the tip: tolerance 40 um
// along the axis, as above (taken as the end, they would put it 0.2 mm too far).
TEST(ThinPart, StrayPointsPastTheTipAreNotTheTip) {
  const auto& t = thread_scene();
  PointCloud scan = t.scan.cloud;
  const Eigen::Vector3d axis = t.truth.rotation().col(2), tip = t.truth.translation();
  Eigen::Vector3d side = t.viewpoint - tip;  // the band faces the sensor
  side = (side - axis * axis.dot(side)).normalized();
  scan.points[0] = (tip + axis * 0.1 + side * 0.075).cast<float>();
  scan.points[1] = (tip + axis * 0.2 + side * 0.075).cast<float>();
  const auto r = reg::register_cloud(scan, t.ref, settings_with_prior(t));
  ASSERT_EQ(r.status, reg::Status::Ambiguous) << r.reason;
  EXPECT_LT(std::abs((r.T_scan_ref.translation() - tip).dot(axis)) * 1e3, 40.0);
}

TEST(ThinPart, FailsWhenNothingOfTheReferencesRadiusIsThere) {
  // A reference three times as thick (225 um): the band the thread shows is too narrow for it.
  const auto& t = thread_scene();
  PointCloud thick = t.ref;
  for (auto& p : thick.points) p.head<2>() *= 3.0f;
  auto s = settings_with_prior(t);
  s.thin.mode = reg::ThinMode::On;
  const auto r = reg::register_cloud(t.scan.cloud, thick, s);
  EXPECT_EQ(r.status, reg::Status::Failed);
  EXPECT_NE(r.reason.find("narrower than the reference"), std::string::npos) << r.reason;
}

TEST(ThinPart, FailsFarFromTheThread) {
  // The prior 15 mm beside the thread (beyond the 10 mm search radius): nothing to find.
  const auto& t = thread_scene();
  auto s = settings_with_prior(t);
  s.prior->translation() += Eigen::Vector3d(0, 0, 15);
  try {
    const auto r = reg::register_cloud(t.scan.cloud, t.ref, s);
    EXPECT_EQ(r.status, reg::Status::Failed) << r.reason;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("near the thin part's prior"), std::string::npos)
        << e.what();
  }
}

TEST(ThinPart, NeedsAPrior) {
  const auto& t = thread_scene();
  reg::RegistrationSettings s;  // neither prior nor q0
  EXPECT_THROW(reg::register_cloud(t.scan.cloud, t.ref, s), Error);
  EXPECT_THROW(parse_enum<reg::ThinMode>("sometimes"), Error);
}
