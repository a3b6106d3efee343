// The laserfit binary as a user runs it: help, --json, and bad input -> exactly one stderr line,
// non-zero exit, no output file left behind.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/json.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {
struct Result {
  int code;
  std::string out, err;
};

Result run(const std::string& args, const test::TempDir& dir) {
  const std::string out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = std::string(LASERFIT_BIN) + " " + args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::read_bytes(out),
          test::read_bytes(err)};
}

size_t lines(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }
const std::string kPanel = test::data("o2ac/02-PANEL.stl").string();
const std::string kPlug = std::string(LASERFIT_SOURCE_DIR) + "/cad/usb_a_plug.ply";
}  // namespace

TEST(Cli, HelpForEverySubcommand) {
  test::TempDir dir;
  EXPECT_EQ(run("--help", dir).code, 0);
  for (const char* sub : {"import", "refcloud", "cad", "scan", "assemble", "register", "bench",
                          "bench generate", "bench merge", "bench export", "tune", "report"}) {
    const auto r = run(std::string(sub) + " --help", dir);
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("--json"), std::string::npos) << sub;
    EXPECT_NE(r.out.find("Exit codes: 0 done; 1 bad input"), std::string::npos) << sub;
  }
  EXPECT_NE(run("frobnicate", dir).code, 0);
}

TEST(Cli, ImportJsonReport) {
  test::TempDir dir;
  const auto r = run("import " + kPanel + " -o " + (dir / "p.ply") + " --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = io::Json::parse(r.out);
  for (const char* key : {"triangles", "vertices", "bbox_mm", "watertight", "unit", "repair"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["triangles"], 1150);
  EXPECT_NEAR(j["bbox_mm"][0].get<double>(), 70.0, 1e-3);
  EXPECT_TRUE(std::filesystem::exists(dir / "p.ply"));
}

TEST(Cli, RefcloudIsSeededAndRecordsItsProvenance) {
  test::TempDir dir;
  const std::string args = "refcloud " + kPlug + " -n 20000 --view-dir 0,0,1 --seed 7 -o ";
  ASSERT_EQ(run(args + (dir / "a.pcd"), dir).code, 0);
  ASSERT_EQ(run(args + (dir / "b.pcd") + " --jobs 1", dir).code, 0);  // one thread everywhere
  EXPECT_TRUE(test::read_bytes(dir / "a.pcd") == test::read_bytes(dir / "b.pcd"));
  EXPECT_EQ(run(args + (dir / "b.pcd") + " --jobs 0", dir).code, 2);
  const auto meta = io::read_header_metadata(dir / "a.pcd");
  EXPECT_EQ(meta.at("seed"), "7");
  EXPECT_EQ(meta.at("views"), "1");
  EXPECT_EQ(meta.at("unit"), "mm");
  EXPECT_TRUE(meta.count("view0.T_mesh_sensor"));
}

TEST(Cli, ScanWritesCloudGroundTruthAndRawProfiles) {
  test::TempDir dir;
  const std::string scene =
      std::string(LASERFIT_SOURCE_DIR) + "/datasets/scenes/needle_thread.yaml";
  const std::string args = "scan " + scene + " --seed 3 --json --gt " + (dir / "gt.json") +
                           " --raw " + (dir / "raw.pcd") + " -o ";
  const auto r = run(args + (dir / "a.pcd"), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(io::Json::parse(r.out)["width"], 2048);
  ASSERT_EQ(run(args + (dir / "b.pcd") + " --jobs 1", dir).code, 0);  // one thread everywhere
  EXPECT_TRUE(test::read_bytes(dir / "a.pcd") == test::read_bytes(dir / "b.pcd"));
  EXPECT_EQ(run(args + (dir / "b.pcd") + " --jobs 0", dir).code, 2);
  const auto gt = io::Json::parse(test::read_bytes(dir / "gt.json"));
  EXPECT_EQ(gt["seed"], 3);
  EXPECT_EQ(gt["objects"].size(), 2u);
  EXPECT_EQ(gt["T_base_sensor_true"].size(), gt["height"].get<size_t>());
  const PointCloud raw = io::read_cloud(dir / "raw.pcd");
  EXPECT_EQ(raw.width, 2048);
  for (const auto& p : raw.points) {
    if (p.allFinite()) {
      ASSERT_EQ(p.y(), 0.f) << "raw profiles are (x, z) in the laser plane";
    }
  }
  // The cell rehearsed: raw profiles + the logged flange poses + the hand-eye, assembled, give
  // the scan back (same grid and gaps, every point within 0.1 um: one float rounding).
  const std::string he = " --hand-eye '1 -2 80 0.9659258262890683 0 0 0.25881904510252074'";
  ASSERT_EQ(run(args + (dir / "c.pcd") + " --flange-poses " + (dir / "flange.csv") + he, dir).code,
            0);
  const auto a = run("assemble --profiles " + (dir / "raw.pcd") + " --poses " +
                         (dir / "flange.csv") + he + " -o " + (dir / "assembled.pcd"),
                     dir);
  ASSERT_EQ(a.code, 0) << a.err;
  const PointCloud scan = io::read_cloud(dir / "a.pcd"),
                   assembled = io::read_cloud(dir / "assembled.pcd");
  ASSERT_EQ(assembled.height, scan.height);
  for (size_t k = 0; k < scan.size(); ++k) {
    ASSERT_EQ(assembled.points[k].allFinite(), scan.points[k].allFinite()) << k;
    if (scan.points[k].allFinite()) {
      ASSERT_LE((assembled.points[k] - scan.points[k]).norm(), 1e-4) << k;
    }
  }
}

// Inputs that once killed the CAD parsers inside laserfit (tests/data/crashes/README.md): now
// each is one line on stderr, exit 1 and no output file (or, should a parser accept one, a
// normal import).
TEST(Cli, CrashingInputsAreOneLineErrors) {
  test::TempDir dir;
  namespace fs = std::filesystem;
  size_t refused = 0;
  for (const auto& e : fs::directory_iterator(test::data("crashes"))) {
    const std::string f = e.path().string(), ext = e.path().extension().string();
    if (ext != ".step" && ext != ".ply" && ext != ".dae") continue;
    const bool refcloud = e.path().filename().string().rfind("refcloud", 0) == 0;
    const std::string out = dir / (refcloud ? "out.pcd" : "out.ply");
    const auto r = run((refcloud ? "refcloud " + f + " -n 1000 -o " : "import " + f + " -o ") +
                           out + " --timeout 30 --reader-memory 4096",
                       dir);
    SCOPED_TRACE(f + ": " + r.err);
    ASSERT_TRUE(r.code == 0 || r.code == 1);
    if (r.code == 1) {
      ++refused;
      EXPECT_EQ(lines(r.err), 1u);
      EXPECT_EQ(r.err.rfind("laserfit ", 0), 0u);
      EXPECT_NE(r.err.find(f), std::string::npos);  // names the file
      EXPECT_FALSE(fs::exists(out));
    }
    fs::remove(out);
  }
  EXPECT_GE(refused, 6u);  // the DAE may import (the parser is cut off or not); the rest cannot
}

TEST(Cli, ParserLimitsAreOneLineErrors) {
  test::TempDir dir;
  const std::string step = test::data("o2ac/02-PANEL.step").string(), out = dir / "o.ply";
  auto r = run("import " + step + " --timeout 0.001 -o " + out, dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "laserfit import: error: " + step +
                       ": the STEP reader took longer than 0.001 s (raise --timeout if the file "
                       "is just large)\n");
  // Usage errors: one line, exit 2, nothing attempted.
  for (const char* args : {"refcloud x.ply -n -5 -o y.pcd", "refcloud x.ply --density -1 -o y.pcd",
                           "import x.step --timeout -1 -o y.ply", "import",
                           "bench export b.yaml -o d"}) {  // no layout chosen
    r = run(args, dir);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
  }
}

// A flat plate registered against itself can slide in its plane: `ambiguous`. --fail-on turns
// that into exit code 3 for scripts, results still printed; without it, or with --fail-on failed,
// the run is done (0). Priors per reference.
TEST(Cli, FailOnGivesExitCode3AndPriorsArePerReference) {
  test::TempDir dir;
  PointCloud plate;
  for (int i = 0; i < 2500; ++i) {
    plate.points.emplace_back(0.2f * (i % 50), 0.2f * (i / 50), 0.f);
    plate.normals.emplace_back(0.f, 0.f, 1.f);
  }
  plate.width = 2500;
  plate.sensor_origin = Eigen::Vector3d(5, 5, 90);
  io::write_cloud(dir / "plate.pcd", plate);
  const std::string reg =
      "register --no-segment --scan " + (dir / "plate.pcd") + " --ref " + (dir / "plate.pcd");
  const auto ambiguous = run(reg + " --fail-on ambiguous", dir);
  EXPECT_EQ(ambiguous.code, 3) << ambiguous.err;
  EXPECT_NE(ambiguous.out.find("ambiguous"), std::string::npos) << ambiguous.out;
  EXPECT_EQ(run(reg + " --fail-on failed", dir).code, 0);
  EXPECT_EQ(run(reg, dir).code, 0);
  EXPECT_EQ(run(reg + " --fail-on maybe", dir).code, 2);
  // One prior per reference, in order: refined from each alone, the plate stays where its own
  // prior put it (it may slide in its plane), to 1 um.
  const auto two =
      run(reg + " --ref " + (dir / "plate.pcd") +
              " --refine-only --json --prior '0 0 0 1 0 0 0' --prior '0.3 0.2 0 1 0 0 0'",
          dir);
  ASSERT_EQ(two.code, 0) << two.err;
  const auto results = io::Json::parse(two.out)["results"];
  ASSERT_EQ(results.size(), 2u);
  EXPECT_NEAR(results[0]["T_scan_ref"]["t_mm"][0].get<double>(), 0.0, 1e-3);
  EXPECT_NEAR(results[1]["T_scan_ref"]["t_mm"][0].get<double>(), 0.3, 1e-3);
  EXPECT_NEAR(results[1]["T_scan_ref"]["t_mm"][1].get<double>(), 0.2, 1e-3);
}

TEST(Cli, BadInputOneLineNonZeroNoOutput) {
  test::TempDir dir;
  test::write_text(dir / "trunc.stl", test::read_bytes(kPanel).substr(0, 700));
  test::write_text(dir / "empty.obj", "");
  {  // a well-formed cloud whose every point is NaN: nothing to register
    PointCloud nan;
    nan.points.assign(100, Eigen::Vector3f::Constant(std::nanf("")));
    nan.width = 100;
    io::write_cloud(dir / "nan.pcd", nan);
  }
  {  // a plate in mm, and the same plate in metres with no unit stated: a unit mix-up
    PointCloud mm, m;
    for (int i = 0; i < 400; ++i) {
      const Eigen::Vector3f p(0.5f * (i % 20), 0.5f * (i / 20), 0.01f * (i % 7));
      mm.points.push_back(p), m.points.push_back(p * 1e-3f);
    }
    mm.width = m.width = 400;
    mm.metadata["unit"] = "mm";
    io::write_cloud(dir / "plate_mm.pcd", mm);
    io::write_cloud(dir / "plate_m.pcd", m);
  }
  const std::string out = dir / "out.ply";
  const std::string cloud = dir / "out.pcd";
  const std::string too_long = dir / (std::string(300, 'n') + ".pcd");
  test::write_text(dir / "prof.csv", "1,90,2,91\n1,90,2,91\n");  // two profiles of two points
  test::write_text(dir / "one_pose.csv", "500 0 200 1 0 0 0\n");
  test::write_text(dir / "two_poses.csv", "500 0 200 1 0 0 0\n500 1 200 1 0 0 0\n");
  std::filesystem::create_directories(dir / "recorded");
  test::write_text(dir / "recorded/scene_gt.json", "{\"0\": [{\"obj_id\": 1}]}");
  test::write_text(dir / "recorded.yaml",  // ground truth without a pose
                   "name: r\nscenes:\n  - {name: a, recorded: recorded, targets: [{object: o, "
                   "obj_id: 1, reference_cloud: plate_mm.pcd}]}\n");
  const std::string assemble =
      "assemble --profiles " + (dir / "prof.csv") + " --hand-eye '0 0 80 1 0 0 0' ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"import " + (dir / "missing.step") + " -o " + out, out},
      {"import " + (dir / "trunc.stl") + " -o " + out, out},
      {"import " + (dir / "empty.obj") + " -o " + out, out},
      {"import " + kPanel + " -o " + (dir / "no_such_dir/out.ply"), dir / "no_such_dir/out.ply"},
      {"import " + kPanel + " -o " + (dir / "out.xyz"), dir / "out.xyz"},
      {"import " + kPanel + " --unit furlong -o " + out, out},
      {"refcloud " + kPlug + " -o " + cloud, cloud},                        // no count/density
      {"refcloud " + kPlug + " -n 100 --view '1 2 3' -o " + cloud, cloud},  // bad pose
      {"refcloud " + kPlug + " -n 100 --view '0 0 500 1 0 0 0' -o " + cloud,
       cloud},  // sees nothing
      {"refcloud " + kPlug + " -n 100 --method best -o " + cloud, cloud},
      {"cad teapot -o " + (dir / "cad"), dir / "cad/teapot.yaml"},
      {"cad needle --set eye_width=9 -o " + (dir / "cad"), dir / "cad/needle.ply"},
      {"scan " + (dir / "missing.yaml") + " -o " + cloud, cloud},
      {"register --scan " + (dir / "missing.pcd") + " --ref " + (dir / "missing_ref.pcd"), ""},
      {"register --scan " + (dir / "trunc.stl") + " --ref " + (dir / "trunc.stl"), ""},
      {"register --scan " + (dir / "nan.pcd") + " --ref " + (dir / "nan.pcd"), ""},
      {"register --scan " + (dir / "plate_m.pcd") + " --ref " + (dir / "plate_mm.pcd"), ""},
      {"register --scan " + (dir / "plate_mm.pcd") + " --ref " + (dir / "plate_mm.pcd") +
           " --unit furlong",
       ""},
      {"register --scan " + too_long + " --ref " + (dir / "plate_mm.pcd"), ""},
      {"register --scan " + (dir / "plate_mm.pcd") + " --ref " + (dir / "plate_mm.pcd") +
           " --prior '0 0 0 1 0 0 0' --prior '1 0 0 1 0 0 0'",
       ""},                                        // two priors for one reference
      {"scan " + kPanel + " -o " + cloud, cloud},  // not a scene file
      {assemble + "--poses " + (dir / "one_pose.csv") + " -o " + cloud, cloud},  // 1 pose, 2 rows
      {assemble + "--poses " + (dir / "prof.csv") + " -o " + cloud, cloud},      // not poses
      {assemble + "--poses " + (dir / "two_poses.csv") + " --width 3 -o " + cloud, cloud},
      {"assemble --profiles " + (dir / "prof.csv") + " --hand-eye '0 0 80' --poses " +
           (dir / "two_poses.csv") + " -o " + cloud,
       cloud},
      {"register --scan " + (dir / "nan.pcd") + " --ref " + (dir / "nan.pcd") + " --thresholds " +
           (dir / "empty.obj"),
       ""},
      {"bench " + (dir / "missing.yaml") + " --out " + (dir / "b"), dir / "b/results.jsonl"},
      {"bench " + kPanel + " --out " + (dir / "b"), dir / "b/results.jsonl"},  // not a benchmark
      {"bench " + std::string(LASERFIT_SOURCE_DIR) + "/benchmarks/quick.yaml --shard 5/4 --out " +
           (dir / "b"),
       dir / "b/results.jsonl"},
      {"bench " + std::string(LASERFIT_SOURCE_DIR) +
           "/benchmarks/quick.yaml --methods magic --out " + (dir / "b"),
       dir / "b/results.jsonl"},
      {"bench merge " + (dir / "nothing") + " -o " + (dir / "m"), dir / "m/results.jsonl"},
      {"bench export " + (dir / "missing.yaml") + " --bop -o " + (dir / "x"),
       dir / "x/benchmark.yaml"},
      {"bench " + (dir / "recorded.yaml") + " --out " + (dir / "b"), dir / "b/results.jsonl"},
      {"tune " + std::string(LASERFIT_SOURCE_DIR) +
           "/benchmarks/quick.yaml --train 0:3 --test 2:4 -o " + (dir / "t.yaml"),
       dir / "t.yaml"},
      {"report " + (dir / "missing.jsonl") + " -o " + (dir / "rep"), dir / "rep/README.md"},
      {"report " + (dir / "empty.obj") + " -o " + (dir / "rep"), dir / "rep/README.md"},
      {"scan " + std::string(LASERFIT_SOURCE_DIR) +
           "/datasets/scenes/needle_thread.yaml --noise maybe -o " + cloud,
       cloud},
  };
  for (const auto& [args, output] : cases) {
    SCOPED_TRACE(args);
    const auto r = run(args, dir);
    EXPECT_NE(r.code, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    if (!output.empty()) {
      EXPECT_FALSE(std::filesystem::exists(output));
    }
  }
  // Nothing half-written anywhere (temporary files included).
  for (const auto& e : std::filesystem::directory_iterator(dir.path))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}
