// Benchmark definitions, trials and shards, thresholds files, and the runner: shards merged equal
// one run, an interrupted run resumes without repeating or losing trials, a dataset on disk gives
// the same records as the scans simulated in memory.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "bench_fixture.hpp"
#include "laserfit/bench/dataset.hpp"
#include "laserfit/bench/runner.hpp"
#include "laserfit/bench/tune.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/metrics/pose_error.hpp"
#include "laserfit/registration/thresholds.hpp"
#include "laserfit/scan/reference.hpp"
#include "test_util.hpp"

using namespace laserfit;
namespace fs = std::filesystem;

namespace {
using test::kSource, test::tiny_benchmark, test::without_timing, test::quiet_run;

// The first target of trial i in dataset `out`: its ground-truth entry, true pose and prior.
struct GtTarget {
  io::Json json;
  Pose truth, prior;
};
GtTarget gt_target(const std::string& out, int i) {
  const std::string gt = out + "/gt/" + std::to_string(i) + ".json";
  const auto t = io::read_json(gt).at("targets").at(0);
  return {t, io::pose_from_json(t.at("T_scan_object"), gt), io::pose_from_json(t.at("prior"), gt)};
}
}  // namespace

TEST(Bench, EveryShippedBenchmarkLoads) {
  for (const auto& e : fs::directory_iterator(kSource + "/benchmarks")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    const auto b = bench::load_benchmark(e.path().string());
    EXPECT_FALSE(bench::enumerate_trials(b).empty());
    for (const auto& sc : b.scenes) EXPECT_TRUE(fs::exists(sc.scene_path)) << sc.scene_path;
  }
}

TEST(Bench, BadDefinitionsAreErrorsNamingTheFile) {
  test::TempDir dir;
  const std::string good =
      "name: x\nscenes:\n  - {name: a, scene: s.yaml, targets: [{object: o}]}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"name: x\ntrails: 3\n" + good.substr(8), "unknown key 'trails'"},
      {"name: x\nconditions: {noise_scale: -1}\n" + good.substr(8), "noise_scale"},
      {"name: x\nmode: random\nconditions: {noise_scale: [3, 1]}\n" + good.substr(8),
       "min above max"},
      {"name: x\n", "missing key 'scenes'"},
      {"name: x\nscenes:\n  - {name: a, scene: s.yaml, targets: [{object: o}]}\n  - {name: a, "
       "scene: s.yaml, targets: [{object: o}]}\n",
       "duplicate"},
      {"name: x\nscenes:\n  - {name: a, scene: s.yaml, targets: [{object: o, weak_rotation: w}]}\n",
       "weak_rotation"},
      {"name: x\nscenes:\n  - {name: a, scene: s.yaml, targets: [{object: o, pivot: middle}]}\n",
       "pivot"},
      {"name: x\nscenes:\n  - {name: a, scene: s.yaml, prior: maybe, targets: [{object: o}]}\n",
       "prior"},
      {"name: x\ntrials: 0\n" + good.substr(8), "trials"},
      {"[1, 2", "not valid YAML"}};
  for (const auto& [text, what] : cases) {
    test::write_text(dir / "b.yaml", text);
    try {
      bench::load_benchmark(dir / "b.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(dir / "b.yaml"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(bench::load_benchmark(dir / "missing.yaml"), Error);
}

TEST(Bench, GridTrialsAreDeterministicAndShardsPartitionThem) {
  test::TempDir dir;
  test::write_text(
      dir / "g.yaml",
      "name: g\ntrials: 5\nconditions: {noise_scale: [0.5, 1, 2], outlier_rate: [0, 0.01]}\n"
      "scenes:\n  - {name: a, scene: s.yaml, targets: [{object: o}]}\n  - {name: b, scene: s.yaml, "
      "targets: [{object: o}]}\n");
  const auto b = bench::load_benchmark(dir / "g.yaml");
  const auto t1 = bench::enumerate_trials(b), t2 = bench::enumerate_trials(b);
  ASSERT_EQ(t1.size(), 2u * 3 * 2 * 5);  // scenes x noise x outliers x repetitions
  std::set<uint64_t> seeds;
  for (size_t i = 0; i < t1.size(); ++i) {
    EXPECT_EQ(t1[i].seed, t2[i].seed);
    EXPECT_EQ(t1[i].index, int(i));
    seeds.insert(t1[i].seed);
  }
  EXPECT_EQ(seeds.size(), t1.size());  // every trial its own seed
  std::vector<int> owner(t1.size(), -1);
  for (int s = 0; s < 4; ++s)
    for (const auto& t : t1)
      if (bench::parse_shard(std::to_string(s) + "/4").contains(t)) {
        EXPECT_EQ(owner[t.index], -1);
        owner[t.index] = s;
      }
  for (int o : owner) EXPECT_GE(o, 0);  // every trial in exactly one shard
  EXPECT_THROW(bench::parse_shard("4/4"), Error);
  EXPECT_THROW(bench::parse_shard("1-4"), Error);
  // --scenes: by name, in the order given; an unknown name is an error naming the file.
  EXPECT_EQ(bench::scene_indices(b, {}), (std::vector<int>{0, 1}));
  EXPECT_EQ(bench::scene_indices(b, {"b"}), (std::vector<int>{1}));
  try {
    bench::scene_indices(b, {"c"});
    ADD_FAILURE() << "unknown scene accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("g.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'c'"), std::string::npos) << e.what();
  }
}

// The true pose turns about the pivot: about the object's origin, the origin stays within
// translation_mm of its nominal place; about the seen part, the seen part's centroid does
// (tolerance 1e-6 mm on top: the poses are stored as doubles in JSON).
TEST(Bench, PerturbationsTurnAboutTheChosenPivot) {
  test::TempDir dir;
  tiny_benchmark(dir);  // writes scene.yaml
  for (const std::string pivot : {"origin", "view", "centre"}) {
    test::write_text(dir / "p.yaml",
                     "name: p\nseed: 5\nmode: random\ntrials: 4\n"
                     "conditions: {rotation_deg: 30, translation_mm: 0.5}\n"
                     "scenes:\n  - name: usb\n    scene: scene.yaml\n    targets:\n"
                     "      - {object: usb_a_receptacle, reference_points: 5000, pivot: " +
                         pivot + "}\n");
    const auto b = bench::load_benchmark(dir / "p.yaml");
    const std::string out = dir / ("d_" + pivot);
    bench::generate_dataset(b, out, 2, {}, {"usb"});
    double origin_moved = 0, rotated = 0;
    for (int i = 0; i < 4; ++i) {
      const auto [t, truth, nominal] = gt_target(out, i);
      const auto pv = t.at("pivot_mm").get<std::vector<double>>();
      const Eigen::Vector3d c(pv[0], pv[1], pv[2]);
      EXPECT_EQ(c.isZero(), pivot == "origin") << c.transpose();
      EXPECT_LE((truth * c - nominal * c).norm(), 0.5 + 1e-6) << pivot << " trial " << i;
      origin_moved = std::max(origin_moved, (truth.translation() - nominal.translation()).norm());
      rotated = std::max(
          rotated, Eigen::AngleAxisd(nominal.rotation().transpose() * truth.rotation()).angle());
    }
    EXPECT_GT(rotated, 10 * M_PI / 180);  // the draws do turn the part
    if (pivot == "view") {
      EXPECT_GT(origin_moved, 0.5) << "the seen part's centroid is away from the origin";
    }
  }
}

// turn_about: z turns the part about the scene's vertical only (a part resting on a table), by
// up to rotation_deg either way. Tolerance 0.05 deg: the truth in the scan frame carries the
// arm's error between the sensor's true and nominal poses (0.008 deg seen).
TEST(Bench, TurnAboutKeepsTheTurnOnOneAxis) {
  test::TempDir dir;
  tiny_benchmark(dir);  // writes scene.yaml
  test::write_text(dir / "z.yaml",
                   "name: z\nseed: 5\nmode: random\ntrials: 6\n"
                   "conditions: {rotation_deg: 90, translation_mm: 0.5}\n"
                   "scenes:\n  - name: usb\n    scene: scene.yaml\n    targets:\n"
                   "      - {object: usb_a_receptacle, reference_points: 5000, turn_about: z}\n");
  const auto b = bench::load_benchmark(dir / "z.yaml");
  const std::string out = dir / "d";
  bench::generate_dataset(b, out, 2, {}, {"usb"});
  double most = 0, least = 0;  // signed turn about +z (deg)
  for (int i = 0; i < 6; ++i) {
    const auto [t, truth, nominal] = gt_target(out, i);
    const Eigen::Matrix3d M = truth.rotation() * nominal.rotation().transpose();
    const double rad = std::atan2(M(1, 0), M(0, 0));  // the turn about z that M is
    const Eigen::Matrix3d Rz = Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_LT(Eigen::AngleAxisd(Rz.transpose() * M).angle() * 180 / M_PI, 0.05) << M;
    const double deg = rad * 180 / M_PI;
    EXPECT_LE(std::abs(deg), 90 + 0.05);
    most = std::max(most, deg), least = std::min(least, deg);
  }
  EXPECT_GT(most, 0);  // both senses are drawn
  EXPECT_LT(least, 0);
  test::write_text(dir / "bad.yaml",
                   "name: z\nscenes:\n  - name: usb\n    scene: scene.yaml\n"
                   "    targets: [{object: o, turn_about: w}]\n");
  EXPECT_THROW(bench::load_benchmark(dir / "bad.yaml"), Error);
}

// prior: none registers globally: the trial carries no prior, its ground-truth file has no
// "prior" and reading that file back keeps it so (exact: flags, not numbers).
TEST(Bench, PriorNoneLeavesTheTrialWithoutAPrior) {
  test::TempDir dir;
  tiny_benchmark(dir);  // writes scene.yaml
  test::write_text(dir / "g.yaml",
                   "name: g\nseed: 5\ntrials: 1\nscenes:\n  - name: usb\n    scene: scene.yaml\n"
                   "    prior: none\n    targets:\n"
                   "      - {object: usb_a_receptacle, reference_points: 5000}\n");
  const auto b = bench::load_benchmark(dir / "g.yaml");
  ASSERT_FALSE(b.scenes[0].use_prior);
  const auto p = bench::prepare_scene(b, 0);
  EXPECT_FALSE(bench::trial_input(b, p, bench::enumerate_trials(b)[0]).has_prior);
  const std::string out = dir / "d";
  bench::generate_dataset(b, out, 1, {}, {"usb"});
  const std::string gt = out + "/gt/0.json";
  EXPECT_FALSE(io::read_json(gt).at("targets").at(0).contains("prior"));
  const auto in = bench::read_trial(p, out + "/scans/0.pcd", gt);
  EXPECT_FALSE(in.has_prior);
  EXPECT_EQ(in.prior.size(), in.truth.size());
}

TEST(Bench, AnOkIsPinnedToTheBenchmarksTolerance) {
  // The trust's jackknife limits are the benchmark's tolerance (exact: copied); the default
  // tolerance is the default trust, so the 50 um benchmarks register as before.
  namespace reg = laserfit::registration;
  bench::Benchmark b;
  const bench::Target tg;
  auto s = bench::method_settings(b, reg::Method::Ceres, tg, nullptr);
  EXPECT_EQ(s.trust.max_sigma_mm, reg::TrustSettings{}.max_sigma_mm);
  EXPECT_EQ(s.trust.max_sigma_deg, reg::TrustSettings{}.max_sigma_deg);
  b.t_tol_mm = 0.005, b.r_tol_deg = 0.05;
  s = bench::method_settings(b, reg::Method::Ceres, tg, nullptr);
  EXPECT_EQ(s.trust.max_sigma_mm, 0.005);
  EXPECT_EQ(s.trust.max_sigma_deg, 0.05);
}

TEST(Bench, UntunedThresholdsAreTheDefaultSettings) {
  // Thresholds are an overlay on RegistrationSettings: an untuned one changes no field (exact).
  namespace reg = laserfit::registration;
  const reg::RegistrationSettings d;
  reg::RegistrationSettings s;
  reg::Thresholds{}.apply(s, "any");
  EXPECT_EQ(s.coarse.feature_radius_vox, d.coarse.feature_radius_vox);
  EXPECT_EQ(s.coarse.ransac_iterations, d.coarse.ransac_iterations);
  EXPECT_EQ(s.refine.max_correspondence_vox, d.refine.max_correspondence_vox);
  EXPECT_EQ(s.refine.method, d.refine.method);
  EXPECT_EQ(s.rho_icp_vox2, d.rho_icp_vox2);
  EXPECT_EQ(s.rho_rot_deg, d.rho_rot_deg);
  EXPECT_EQ(s.trust.max_rmse_vox, d.trust.max_rmse_vox);
  EXPECT_EQ(s.trust.min_overlap, d.trust.min_overlap);
  EXPECT_EQ(s.pre.voxel_mm, d.pre.voxel_mm);
}

TEST(Bench, ThresholdsRoundTripAndAreValidated) {
  test::TempDir dir;
  registration::Thresholds t;
  t.rho_rot_deg = 15, t.rho_icp_vox2 = 0.02, t.ransac_iterations = 2000,
  t.voxel_mm["needle"] = 0.03;
  t.benchmark = "quick", t.seed = 7, t.train = "0:3", t.test = "3:6", t.held_out_registrations = 9;
  t.held_out_success_rate = 0.875;
  registration::write_thresholds(dir / "t.yaml", t);
  const auto back = registration::load_thresholds(dir / "t.yaml");
  EXPECT_EQ(back.rho_rot_deg, 15);
  EXPECT_EQ(back.ransac_iterations, 2000);
  EXPECT_EQ(back.voxel_mm.at("needle"), 0.03);
  EXPECT_EQ(back.seed, 7u);
  EXPECT_EQ(back.held_out_success_rate, 0.875);
  registration::RegistrationSettings s;
  back.apply(s, "needle");
  EXPECT_EQ(s.pre.voxel_mm, 0.03);
  EXPECT_EQ(s.rho_rot_deg, 15);

  const std::string text = registration::thresholds_yaml(t);
  auto broken = [&](const std::string& from, const std::string& to) {
    std::string x = text;
    const auto at = x.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    x.replace(at, from.size(), to);
    test::write_text(dir / "bad.yaml", x);
  };
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"rho_rot: {value: 15, unit: \"deg\"}", "rho_rot: {value: 15, unit: \"rad\"}",
       "expected 'deg'"},
      {"rho_rot: {value: 15,", "rho_rot: {value: 500,", "out of range"},
      {"  rho_icp:", "  rho_icp_typo:", "unknown key"},
      {"  min_overlap: {value: 0.3, unit: \"fraction\"}\n", "", "missing key 'min_overlap'"},
      {"schema: laserfit.thresholds/1", "schema: laserfit.thresholds/9", "schema"},
      {"method: ceres", "method: magic", "unknown registration method"},
      {"voxel: {value: 0.03,", "voxel: {value: .nan,", "not a finite number"}};
  for (const auto& [from, to, what] : cases) {
    broken(from, to);
    try {
      registration::load_thresholds(dir / "bad.yaml");
      ADD_FAILURE() << "accepted " << to;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
    }
  }
}

// Tolerances: records compared exactly (every field but the measured timings).
TEST(Bench, ShardsMergedEqualOneRunAndAnInterruptedRunResumes) {
  test::TempDir dir;
  const auto b = bench::load_benchmark(tiny_benchmark(dir, 4));
  bench::run_benchmark(b, quiet_run(dir / "single"));
  const auto single = without_timing(bench::read_results(dir / "single/results.jsonl"));
  ASSERT_EQ(single.size(), 4u);
  for (const auto& r : single)
    EXPECT_GT(r.at("visible_points").get<long>(), 1000);  // the socket is in view
  std::vector<std::string> shards;
  for (int i = 0; i < 2; ++i) {
    auto s = quiet_run(dir / ("shard" + std::to_string(i)));
    s.shard = bench::parse_shard(std::to_string(i) + "/2");
    s.jobs = 1;
    bench::run_benchmark(b, s);
    shards.push_back(s.out_dir);
  }
  bench::merge_runs(shards, dir / "merged");
  EXPECT_EQ(without_timing(bench::read_results(dir / "merged/results.jsonl")), single);
  EXPECT_THROW(bench::merge_runs({shards[0]}, dir / "half"), Error);  // a shard missing

  // Interrupted: the journal holds the header, trial 1 and a torn line (killed mid-write).
  const std::string journal = test::read_bytes(dir / "single/results.jsonl");
  fs::create_directories(dir / "resumed");
  io::Json header = io::read_json(dir / "single/run.json");
  for (const char* k :
       {"jobs", "dataset", "trials", "resumed", "records", "wall_s", "trials_per_s"})
    header.erase(k);
  header["file"] = "/another/spelling/of/tiny.yaml";  // the content, not the path, is the run
  const auto all = bench::read_results(dir / "single/results.jsonl");
  std::vector<io::Json> trial1;
  for (const auto& r : all)
    if (r.at("trial") == 1) trial1.push_back(r);
  test::write_text(dir / "resumed/journal.jsonl",
                   header.dump() + "\n" + io::Json{{"trial", 1}, {"records", trial1}}.dump() +
                       "\n{\"trial\": 2, \"rec");
  const auto sum = bench::run_benchmark(b, quiet_run(dir / "resumed"));
  EXPECT_EQ(sum.resumed, 1u);  // trial 1 not repeated, the torn trial 2 run again
  EXPECT_EQ(sum.trials, 4u);
  EXPECT_EQ(without_timing(bench::read_results(dir / "resumed/results.jsonl")), single);
  EXPECT_FALSE(fs::exists(dir / "resumed/journal.jsonl"));

  // A journal of another run is refused, not mixed in.
  fs::create_directories(dir / "other");
  header["methods"] = {"gicp"};
  test::write_text(dir / "other/journal.jsonl", header.dump() + "\n");
  EXPECT_THROW(bench::run_benchmark(b, quiet_run(dir / "other")), Error);
}

// An unsuccessful record whose target left fewer than kMinVisiblePoints in the scan counts as
// "not visible"; a visible miss, a success, or a record without the count (older runs) does not.
TEST(Bench, UnsuccessfulRecordsOfAbsentTargetsAreCountedApart) {
  auto rec = [](bool success, long visible, int determinable = -1) {
    io::Json r = {{"success", success},
                  {"false_accept", false},
                  {"status", success ? "ok" : "failed"},
                  {"expect", "pose"},
                  {"t_err_um", 1.0},
                  {"r_err_deg", 0.01},
                  {"timing", {{"time_s", 0.1}, {"peak_rss_mb", 10.0}}}};
    if (visible >= 0) r["visible_points"] = visible;
    if (determinable >= 0) r["determinable"] = determinable == 1;
    return r;
  };
  const std::vector<io::Json> rs = {rec(false, bench::kMinVisiblePoints - 1, 0),
                                    rec(false, bench::kMinVisiblePoints, 1),
                                    rec(true, 3, 1),
                                    rec(false, -1),
                                    rec(false, 0, 0),
                                    rec(true, bench::kMinVisiblePoints + 5, 1)};
  std::vector<const io::Json*> ptr;
  for (const auto& r : rs) ptr.push_back(&r);
  const auto g = bench::group_stats(ptr);
  EXPECT_EQ(g.not_visible, 2);
  EXPECT_EQ(g.failed, 4);
  // Determinable: the visible ones marked so and the record without the field (an older run),
  // 1 success of 3. The success on 3 points is marked determinable, but its target was not in
  // view, so the refinement from the truth that said so proves nothing.
  EXPECT_EQ(g.determinable, 3);
  EXPECT_EQ(g.determinable_successes, 1);
  EXPECT_NEAR(g.determinable_success_rate(), 1.0 / 3, 1e-12);
  EXPECT_FALSE(bench::determinable(rs[2]));
  EXPECT_TRUE(bench::determinable(rs[3]));
}

// A baseline's record (no check at the truth) takes its scan's facts from laserfit's record of the
// same trial and object, and only from that one.
TEST(Bench, BaselineRecordsShareTheScanFactsOfTheirTrial) {
  auto rec = [](const char* method, int trial, const char* object) {
    return io::Json{{"benchmark", "b"}, {"method", method}, {"trial", trial}, {"object", object}};
  };
  std::vector<io::Json> rs = {rec("ceres", 3, "plug"), rec("open3d", 3, "plug"),
                              rec("open3d", 3, "socket"), rec("open3d", 4, "plug")};
  rs[0]["determinable"] = false, rs[0]["visible_points"] = 7;
  EXPECT_EQ(bench::share_scan_facts(rs), 1u);
  EXPECT_FALSE(rs[1].at("determinable").get<bool>());
  EXPECT_EQ(rs[1].at("visible_points").get<long>(), 7);
  EXPECT_EQ(rs[1].at("scan_facts_from"), "ceres");
  EXPECT_FALSE(rs[2].contains("determinable"));  // another object
  EXPECT_FALSE(rs[3].contains("determinable"));  // another trial
  EXPECT_FALSE(rs[0].contains("scan_facts_from"));
}

TEST(Bench, DatasetIsByteIdenticalAndGivesTheSameRecordsAsMemory) {
  test::TempDir dir;
  const auto b = bench::load_benchmark(tiny_benchmark(dir, 2));
  bench::generate_dataset(b, dir / "d1", 2);
  bench::generate_dataset(b, dir / "d2", 1);
  for (const char* f : {"manifest.json", "scans/0.pcd", "scans/1.pcd", "gt/1.json",
                        "refs/usb_usb_a_receptacle.pcd"})
    EXPECT_EQ(test::read_bytes(dir / (std::string("d1/") + f)),
              test::read_bytes(dir / (std::string("d2/") + f)))
        << f;
  EXPECT_NO_THROW(bench::verify_dataset(dir / "d1"));

  auto from_disk = quiet_run(dir / "disk");
  from_disk.dataset_dir = dir / "d1";
  bench::run_benchmark(b, from_disk);
  bench::run_benchmark(b, quiet_run(dir / "memory"));
  EXPECT_EQ(without_timing(bench::read_results(dir / "disk/results.jsonl")),
            without_timing(bench::read_results(dir / "memory/results.jsonl")));
  // The receptacle is in full view: refined from its true pose it is `ok` within the benchmark's
  // tolerance (50 um, 0.5 deg), so every record says its pose is determinable.
  for (const auto& r : bench::read_results(dir / "disk/results.jsonl")) {
    EXPECT_TRUE(r.at("determinable").get<bool>()) << r.dump();
    EXPECT_EQ(r.at("at_truth").at("status"), "ok") << r.dump();
  }

  // One flipped byte in a scan: verification and the runner both name the file.
  std::string scan = test::read_bytes(dir / "d2/scans/1.pcd");
  scan[scan.size() / 2] ^= 0x5a;
  test::write_text(dir / "d2/scans/1.pcd", scan);
  try {
    bench::verify_dataset(dir / "d2");
    ADD_FAILURE() << "corruption not detected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scans/1.pcd"), std::string::npos) << e.what();
  }
  auto corrupt = quiet_run(dir / "corrupt");
  corrupt.dataset_dir = dir / "d2";
  EXPECT_THROW(bench::run_benchmark(b, corrupt), Error);
}

// Turned 40 deg, the socket shows the scanner other walls than the nominal view reference holds.
// Refined from the truth against that reference, the mismatch held repetition 5's pose; against
// what the scanner sees of the socket at its true pose, one translation is flat, so the scan does
// not determine it. Repetition 4 is held either way: the check is
// not simply failing. (Both seen with this seed; tolerance: the benchmark's 50 um / 0.5 deg.)
TEST(Bench, TheCheckAtTheTruthSeesThePartAsItIsTurned) {
  test::TempDir dir;
  tiny_benchmark(dir);  // the scene
  test::write_text(dir / "turned.yaml",
                   "name: turned\nseed: 3\nmode: random\ntrials: 8\nmethods: [ceres]\n"
                   "conditions: {rotation_deg: 40, translation_mm: 0.5}\n"
                   "scenes:\n  - name: usb\n    scene: scene.yaml\n    targets:\n"
                   "      - {object: usb_a_receptacle, symmetry: none, reference_points: 20000}\n");
  const auto b = bench::load_benchmark(dir / "turned.yaml");
  const bench::PreparedScene p = bench::prepare_scene(b, 0);
  for (const auto& t : bench::select_trials(b, {4, 5}, {})) {
    const bench::TrialInput in = bench::simulate_trial(b, p, t);
    const bench::AtTruth a = bench::at_truth(b, p, t, in, 0, nullptr);
    if (t.repetition == 4) {
      EXPECT_TRUE(a.determinable) << a.status << ": " << a.reason;
      EXPECT_EQ(a.status, "ok") << a.reason;
    } else {
      EXPECT_FALSE(a.determinable) << a.status << ": " << a.reason;
      EXPECT_EQ(a.status, "ambiguous") << a.reason;
      EXPECT_NE(a.reason.find("unobservable translation"), std::string::npos) << a.reason;
    }
  }
}

// registration.yaml's USB receptacle, repetition 70: turned 18 deg from the nominal pose, it fits
// the view reference sampled there at 24 um RMS and RANSAC never confirms the first attempt's
// (right) pose: `failed`. Registered again against its view at that pose, it is `ok` within the
// benchmark's tolerance (50 um, 0.5 deg; 17.5 um and 0.09 deg seen).
TEST(Bench, TheViewResampledAtThePoseFoundConfirmsATurnedSocket) {
  const auto b = bench::load_benchmark(kSource + "/benchmarks/registration.yaml");
  const int scene = bench::scene_indices(b, {"usb"}).at(0);
  const bench::PreparedScene p = bench::prepare_scene(b, scene);
  const bench::Trial t = bench::select_trials(b, {70}, {"usb"}).at(0);
  const bench::TrialInput in = bench::simulate_trial(b, p, t);
  const size_t k = 1;
  const bench::Target& tg = b.scenes[scene].targets[k];
  ASSERT_EQ(tg.object, "usb_a_receptacle");
  auto rs = bench::method_settings(b, registration::Method::Ceres, tg, nullptr);
  rs.q0 = Eigen::Quaterniond(in.prior[k].rotation()), rs.prior = in.prior[k], rs.seed = t.seed;
  ASSERT_TRUE(in.scan.sensor_origin);
  rs.pre.use_viewpoint = true, rs.pre.viewpoint = *in.scan.sensor_origin;
  const auto once = registration::register_segmented(in.scan, p.reference[k], rs, 2);
  EXPECT_EQ(once.status, registration::Status::Failed) << once.reason;
  int sampled = 0;
  const auto view = [&](const Pose& T_scan_ref) {
    ++sampled;
    return scan::view_reference(p.reference_mesh[k], T_scan_ref, p.scene.settings,
                                tg.reference_points, b.seed);
  };
  const auto twice = registration::register_in_view(in.scan, p.reference[k], view, rs, 2);
  EXPECT_EQ(sampled, 1);
  EXPECT_EQ(twice.status, registration::Status::Ok) << twice.reason;
  const auto e = metrics::pose_error(twice.T_scan_ref, in.truth[k], tg.symmetry, p.model[k]);
  EXPECT_LT(e.t_mm, 0.05);
  EXPECT_LT(e.r_deg, 0.5);
}

TEST(Bench, TuningWritesAValidatedThresholdsFileWithItsProvenance) {
  test::TempDir dir;
  const auto b = bench::load_benchmark(tiny_benchmark(dir, 2));
  bench::TuneSettings s;
  s.train = {0}, s.test = {1}, s.params = {"rho_rot"}, s.jobs = 2, s.progress = false;
  const auto r = bench::tune(b, s);
  registration::write_thresholds(dir / "t.yaml", r.thresholds);
  const auto t = registration::load_thresholds(dir / "t.yaml");
  EXPECT_EQ(t.benchmark, "tiny");
  EXPECT_EQ(t.seed, 3u);
  EXPECT_EQ(t.train, "0:1");
  EXPECT_EQ(t.test, "1:2");
  EXPECT_EQ(t.held_out_registrations, 1);  // one held-out trial, one target
  EXPECT_EQ(r.history.size(), 3u);         // defaults + the two other rho_rot candidates
  EXPECT_FALSE(r.baseline_train.better_than(r.best_train));  // never keeps a worse setting
  s.test = {0};
  EXPECT_THROW(bench::tune(b, s), Error);  // overlapping splits
}
