// Recorded scenes (a lab's own scans with BOP ground truth): read and scored exactly as simulated
// scans, in any stated unit, with or without a prior; bad ground truth is one error naming it.
#include <gtest/gtest.h>

#include <filesystem>

#include "bench_fixture.hpp"
#include "laserfit/bench/recorded.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"

using namespace laserfit;
namespace fs = std::filesystem;

namespace {

std::vector<io::Json> comparable(std::vector<io::Json> rs) {
  rs = test::without_timing(rs);
  for (auto& r : rs) r.erase("conditions"), r.erase("image");
  return rs;
}

void expect_error_naming(const std::string& file, const std::function<void()>& f,
                         const std::string& words) {
  try {
    f();
    ADD_FAILURE() << "no error for " << words;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

}  // namespace

// The exported scans, ground truth and references, run as recorded scenes, give the simulated
// run's records exactly (same seeds, same bytes): a lab's dataset is scored by the same rule.
TEST(Recorded, ExportedBenchmarkScoresExactlyLikeTheSimulatedOne) {
  test::TempDir dir;
  const auto b = bench::load_benchmark(test::tiny_benchmark(dir, 2, "methods: [ceres, paper]\n"));
  const auto s = bench::export_bop(b, dir / "bop", 2);
  EXPECT_EQ(s.trials, 2u);
  for (const char* f : {"benchmark.yaml", "models/models_info.json", "models/obj_000001.ply",
                        "refs/usb_usb_a_receptacle.pcd", "usb/scene_gt.json",
                        "usb/scene_prior.json", "usb/scans/000000.pcd", "usb/scans/000001.pcd"})
    EXPECT_TRUE(fs::is_regular_file(dir / (std::string("bop/") + f))) << f;
  const auto rec = bench::load_benchmark(dir / "bop/benchmark.yaml");
  ASSERT_EQ(rec.scenes.size(), 1u);
  ASSERT_EQ(bench::enumerate_trials(rec).size(), 2u);
  EXPECT_EQ(bench::enumerate_trials(rec)[1].image, 1);
  bench::run_benchmark(b, test::quiet_run(dir / "sim"));
  bench::run_benchmark(rec, test::quiet_run(dir / "rec"));
  const auto a = bench::read_results(dir / "sim/results.jsonl");
  const auto r = bench::read_results(dir / "rec/results.jsonl");
  EXPECT_EQ(comparable(a), comparable(r));
  EXPECT_EQ(r.at(1).at("image"), 0);

  // Scene names become directories of the export: one that is a path is refused, nothing written.
  std::string yaml = test::read_bytes(dir / "tiny.yaml");
  yaml.replace(yaml.find("- name: usb"), 11, "- name: ../up");
  test::write_text(dir / "up.yaml", yaml);
  expect_error_naming(
      "up.yaml", [&] { bench::export_bop(bench::load_benchmark(dir / "up.yaml"), dir / "up"); },
      "cannot name a file");
  EXPECT_FALSE(fs::exists(dir / "up"));
}

// Ground truth as another tool writes it: rotations rounded to 7 digits are projected back onto
// a rotation (within 1e-6 of the exact one), and the file round-trips bit for bit.
TEST(Recorded, SceneGtRoundTripsAndRoundedRotationsAreAccepted) {
  test::TempDir dir;
  bench::PoseTable t;
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(500.123456789, -0.5, 100.25);
  t[7][3] = T;
  bench::write_scene_gt(dir / "gt.json", t);
  const auto back = bench::read_scene_gt(dir / "gt.json");
  EXPECT_EQ(back.at(7).at(3).matrix(), T.matrix());  // bit for bit
  std::ostringstream rounded;
  rounded.precision(7);
  rounded << "{\"7\": [{\"obj_id\": 3, \"cam_R_m2c\": [";
  for (int i = 0; i < 9; ++i) rounded << (i ? ", " : "") << T.linear()(i / 3, i % 3);
  rounded << "], \"cam_t_m2c\": [500.1235, -0.5, 100.25]}]}";
  test::write_text(dir / "rounded.json", rounded.str());
  const Pose R = bench::read_scene_gt(dir / "rounded.json").at(7).at(3);
  EXPECT_LT((R.linear() - T.linear()).norm(), 1e-6);
  EXPECT_LT((R.linear() * R.linear().transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(Recorded, BadGroundTruthIsAnErrorNamingTheFile) {
  test::TempDir dir;
  const std::string rot = "\"cam_R_m2c\": [1,0,0,0,1,0,0,0,1]";
  for (const auto& [text, words] : std::vector<std::pair<std::string, std::string>>{
           {"[]", "not BOP's scene_gt layout"},
           {"{}", "lists no image"},
           {"{\"a\": []}", "is not a number"},
           {"{\"0\": [{" + rot + "}]}", "integer obj_id"},
           {"{\"0\": [{\"obj_id\": 1, " + rot + "}]}", "cam_t_m2c"},
           {"{\"0\": [{\"obj_id\": 1, \"cam_R_m2c\": [1,0,0,0,1,0,0,0,2], \"cam_t_m2c\": "
            "[0,0,0]}]}",
            "not a rotation"},
           {"{\"0\": [{\"obj_id\": 1, \"cam_R_m2c\": [1,0,0,0,1,0,0,0,-1], \"cam_t_m2c\": "
            "[0,0,0]}]}",
            "not a rotation"},
           {"{\"0\": [{\"obj_id\": 1, " + rot + ", \"cam_t_m2c\": [0,0,1e400]}]}", "scene_gt"},
           {"{\"0\": [{\"obj_id\": 1, " + rot + ", \"cam_t_m2c\": [0,0,0]}, {\"obj_id\": 1, " +
                rot + ", \"cam_t_m2c\": [0,0,0]}]}",
            "listed twice"}}) {
    test::write_text(dir / "scene_gt.json", text);
    expect_error_naming(
        "scene_gt.json", [&] { bench::read_scene_gt(dir / "scene_gt.json"); }, words);
  }
}

// A lab's folder: scans in metres that do not say so (unit: m in the benchmark), no prior (every
// method registers globally), one scan missing an object, and poses in the wrong unit.
TEST(Recorded, UnitsPriorsAndMissingEntriesOfALabsFolder) {
  test::TempDir dir;
  const auto b = bench::load_benchmark(test::tiny_benchmark(dir, 1));
  bench::export_bop(b, dir / "bop", 1);
  const std::string scan = dir / "bop/usb/scans/000000.pcd";
  PointCloud c = io::read_cloud(scan);
  for (auto& p : c.points) p *= 1e-3f;
  *c.sensor_origin *= 1e-3;
  io::write_cloud(scan, c);
  std::string bytes = test::read_bytes(scan);  // a file that does not state its unit
  bytes.erase(bytes.find("# laserfit.unit mm\n"), 19);
  test::write_text(scan, bytes);
  fs::remove(dir / "bop/usb/scene_prior.json");
  std::string yaml = test::read_bytes(dir / "bop/benchmark.yaml");
  yaml.replace(yaml.find("    recorded: usb\n"), 18, "    recorded: usb\n    unit: m\n");
  test::write_text(dir / "bop/benchmark.yaml", yaml);
  const auto rec = bench::load_benchmark(dir / "bop/benchmark.yaml");
  const auto p = bench::prepare_scene(rec, 0);
  EXPECT_FALSE(rec.scenes[0].has_prior);
  const auto in = bench::trial_input(rec, p, bench::enumerate_trials(rec).at(0));
  EXPECT_FALSE(in.has_prior);
  // Read as metres: the scan is back where the simulated one was (float rounding of 0.5 m:
  // well under 0.1 um).
  const auto sim = bench::trial_input(b, bench::prepare_scene(b, 0), bench::enumerate_trials(b)[0]);
  ASSERT_EQ(in.scan.points.size(), sim.scan.points.size());
  for (size_t i = 0; i < in.scan.points.size(); i += 997)
    if (sim.scan.points[i].allFinite()) {
      EXPECT_LT((in.scan.points[i] - sim.scan.points[i]).norm(), 1e-4f) << i;
    }
  // Globally registered, with no prior, the receptacle in full view is still found: within the
  // benchmark's 50 um / 0.5 deg.
  bench::run_benchmark(rec, test::quiet_run(dir / "rec"));
  const auto r = bench::read_results(dir / "rec/results.jsonl");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(r[0].at("success").get<bool>()) << r[0].dump();

  // The ground truth written in metres puts the part 0.5 m away from the scan: refused.
  bench::PoseTable gt = bench::read_scene_gt(dir / "bop/usb/scene_gt.json");
  gt[0][1].translation() *= 1e-3;
  bench::write_scene_gt(dir / "bop/usb/scene_gt.json", gt);
  const auto metres = bench::load_benchmark(dir / "bop/benchmark.yaml");
  expect_error_naming(
      "scene_gt.json",
      [&] {
        bench::trial_input(metres, bench::prepare_scene(metres, 0),
                           bench::enumerate_trials(metres)[0]);
      },
      "is the unit right");
  gt[0].erase(1);
  gt[0][9] = Pose::Identity();
  bench::write_scene_gt(dir / "bop/usb/scene_gt.json", gt);
  const auto missing = bench::load_benchmark(dir / "bop/benchmark.yaml");
  expect_error_naming(
      "scene_gt.json",
      [&] {
        bench::trial_input(missing, bench::prepare_scene(missing, 0),
                           bench::enumerate_trials(missing)[0]);
      },
      "has no obj_id 1");
}

TEST(Recorded, DefinitionsSayWhatARecordedSceneNeeds) {
  test::TempDir dir;
  test::write_text(dir / "scene_gt.json",
                   "{\"0\": [{\"obj_id\": 1, \"cam_R_m2c\": [1,0,0,0,1,0,0,0,1], "
                   "\"cam_t_m2c\": [0,0,0]}]}");
  const std::string head = "name: x\nscenes:\n  - {name: a, ";
  for (const auto& [scene, words] : std::vector<std::pair<std::string, std::string>>{
           {"recorded: ., targets: [{object: o, reference_cloud: r.pcd}]}", "obj_id"},
           {"recorded: ., targets: [{object: o, obj_id: 1}]}", "no scanner model"},
           {"recorded: ., targets: [{object: o, obj_id: 1, reference: full}]}", "reference_mesh"},
           {"recorded: ., unit: auto, targets: [{object: o, obj_id: 1, reference_cloud: r.pcd}]}",
            "stated"},
           {"recorded: ., scene: s.yaml, targets: [{object: o}]}", "either scene"},
           {"scene: s.yaml, targets: [{object: o, obj_id: 1}]}", "belong to recorded"},
           {"scene: s.yaml, unit: m, targets: [{object: o}]}", "belongs to recorded"},
           {"recorded: nowhere, targets: [{object: o, obj_id: 1, reference_cloud: r.pcd}]}",
            "scene_gt.json"}}) {
    test::write_text(dir / "b.yaml", head + scene + "\n");
    expect_error_naming(
        "", [&] { bench::load_benchmark(dir / "b.yaml"); }, words);
  }
  test::write_text(dir / "c.yaml",
                   "name: x\nconditions: {noise_scale: 2}\nscenes:\n  - {name: a, recorded: ., "
                   "targets: [{object: o, obj_id: 1, reference_cloud: r.pcd}]}\n");
  expect_error_naming(
      "c.yaml", [&] { bench::load_benchmark(dir / "c.yaml"); }, "recorded");
}
