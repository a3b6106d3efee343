// laserfit-controller correct, end to end: the files a lab hands it (a scan, the two references,
// the arm's flange pose, the target prior, thresholds) become the trajectory the library plans
// on the same scan, from a measurement that holds the part where it truly is relative to the
// target, in any stated unit; and a flange pose it cannot trust is one error line and no
// trajectory.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "laserfit/controller/sim.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/robot/motion.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {

const std::string kSource = LASERFIT_SOURCE_DIR;

std::string pose_text(const Pose& T) {
  const auto v = pose_to_tq(T);
  std::ostringstream s;
  s.precision(17);
  for (int i = 0; i < 7; ++i) s << (i ? " " : "") << v[i];
  return s.str();
}

struct Output {
  int code = 0;
  std::string out, err;
};
Output run_controller(const std::string& args, const test::TempDir& dir) {
  const std::string out = dir / "stdout", err = dir / "stderr";
  const int rc = std::system(
      (std::string(LASERFIT_CONTROLLER_BIN) + " " + args + " > " + out + " 2> " + err).c_str());
  return {WEXITSTATUS(rc), test::read_bytes(out), test::read_bytes(err)};
}

std::vector<double> last_row(const std::string& csv) {
  std::istringstream in(test::read_bytes(csv));
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::vector<double> v;
  std::istringstream row(last);
  for (std::string x; std::getline(row, x, ',');) v.push_back(std::stod(x));
  return v;
}

}  // namespace

TEST(Correct, FromFilesItPlansWhatTheLibraryPlansOnATrueMeasurement) {
  test::TempDir dir;
  const std::string cell_file = kSource + "/cells/usb.yaml";
  const std::string thresholds = kSource + "/reports/paper/thresholds_usb.yaml";
  const auto cs = cell::load_cell(cell_file);
  auto s = controller::settings_for(cs);
  s.thresholds = registration::load_thresholds(thresholds);
  const cell::Cell c(cs, 0);  // `correct` uses the believed quantities only
  const auto su = controller::prepare_setting(c, 0, s, 3);
  // The assembling arm approaches from start 1 as the laser strategies do (IC2); the part ends
  // where its true kinematics put it, and the sensing arm scans the cell as it truly is.
  Pose approach = cs.T_target_part_insert;
  approach.translation() = cs.approach_mm;
  laserfit::Mt19937_64 g(5);
  robot::Repeatability rep(cs.arm_errors);
  const robot::Joints q =
      robot::move_cartesian(c.nominal, su.q_start[0],
                            c.flange_for_part(su.T_world_target_believed * approach), su.q_ic2_ref,
                            s.motion)
          .q;
  const Pose part = c.part_true(q, rep, g);
  io::write_cloud(dir / "scan.pcd", controller::scan_cell(c, su, part, 11, g));
  io::write_cloud(dir / "target.pcd", su.target_ref);
  io::write_cloud(dir / "part.pcd", su.part_ref);
  const std::string ee = pose_text(c.nominal.fk(q)), prior = pose_text(su.T_world_target_believed);
  const std::string args = "correct --cell " + cell_file + " --scan " + (dir / "scan.pcd") +
                           " --target-ref " + (dir / "target.pcd") + " --part-ref " +
                           (dir / "part.pcd") + " --ee-pose '" + ee + "' --target-prior '" + prior +
                           "' --thresholds " + thresholds + " --json -o ";
  const Output r = run_controller(args + (dir / "traj.csv"), dir);
  ASSERT_EQ(r.code, 0) << r.err;

  // The library on the same files.
  std::vector<std::string> log;
  const Pose flange = parse_pose(ee);
  const auto m =
      controller::measure(io::read_cloud(dir / "scan.pcd"), io::read_cloud(dir / "target.pcd"),
                          io::read_cloud(dir / "part.pcd"), parse_pose(prior),
                          c.part_believed_from_flange(flange), cs, s, 1, log);
  ASSERT_TRUE(m.ok) << m.reason;
  // The part relative to the target is frame-free: measured in the scan, it is the truth within
  // 20 um and 0.2 deg (both registrations' errors, a few um each on the USB pair).
  const Pose measured = m.T_scan_target.inverse() * m.T_scan_part;
  const Pose truth = su.T_world_target.inverse() * part;
  EXPECT_LT((measured.translation() - truth.translation()).norm(), 0.020);
  EXPECT_LT(Eigen::AngleAxisd(measured.linear().transpose() * truth.linear()).angle() * 180 / M_PI,
            0.2);
  const auto tr =
      controller::plan(c, flange, controller::compute_correction(m, approach, false).delta, s);
  ASSERT_TRUE(tr.ok) << tr.reason;
  const auto json = io::Json::parse(r.out);
  EXPECT_EQ(json.at("samples").get<size_t>(), tr.samples.size());
  // The CSV's last row is the library's end pose (12 significant digits: 1e-9 mm, 1e-11).
  const auto row = last_row(dir / "traj.csv");
  const auto end = pose_to_tq(tr.samples.back().T_base_flange);
  ASSERT_EQ(row.size(), 8u);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(row[1 + i], end[i], 1e-6) << i;
  for (int i = 3; i < 7; ++i) EXPECT_NEAR(row[1 + i], end[i], 1e-9) << i;

  // The flange pose in metres (no --unit): the part is found ~0.5 m from where that pose puts it.
  // No correction, one error line, nothing written.
  Pose metres = flange;
  metres.translation() *= 1e-3;
  const Output bad = run_controller(
      "correct --cell " + cell_file + " --scan " + (dir / "scan.pcd") + " --target-ref " +
          (dir / "target.pcd") + " --part-ref " + (dir / "part.pcd") + " --ee-pose '" +
          pose_text(metres) + "' --target-prior '" + prior + "' --thresholds " + thresholds +
          " -o " + (dir / "bad.csv"),
      dir);
  EXPECT_EQ(bad.code, 1) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_NE(bad.err.find("from where --ee-pose puts it"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.csv"));

  // Said to be metres (--unit m), the same poses give the same trajectory: the clouds state
  // their unit (mm) and keep it, the poses are scaled (to 1e-6 mm of the mm run's end pose).
  Pose prior_m = parse_pose(prior);
  prior_m.translation() *= 1e-3;
  const Output in_m = run_controller(
      "correct --unit m --cell " + cell_file + " --scan " + (dir / "scan.pcd") + " --target-ref " +
          (dir / "target.pcd") + " --part-ref " + (dir / "part.pcd") + " --ee-pose '" +
          pose_text(metres) + "' --target-prior '" + pose_text(prior_m) + "' --thresholds " +
          thresholds + " -o " + (dir / "m.csv"),
      dir);
  ASSERT_EQ(in_m.code, 0) << in_m.err;
  const auto row_m = last_row(dir / "m.csv");
  ASSERT_EQ(row_m.size(), 8u);
  for (int i = 1; i < 8; ++i) EXPECT_NEAR(row_m[i], row[i], 1e-6) << i;
}
