// bench merge refuses anything that is not exactly one run, and one run is exactly what comes
// out; a second writer into a run's directory is refused. Shards are written here by
// write_results from made-up records (the merge reads only files), so the checks take
// milliseconds; test_bench's ShardsMergedEqualOneRun runs real trials.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <boost/iostreams/filter/lzma.hpp>
#include <boost/iostreams/filtering_stream.hpp>
#include <filesystem>
#include <fstream>

#include "laserfit/bench/dataset.hpp"
#include "laserfit/bench/runner.hpp"
#include "laserfit/core/error.hpp"
#include "test_util.hpp"

using namespace laserfit;
namespace fs = std::filesystem;

namespace {

io::Json record(int trial) {
  return {{"trial", trial},
          {"method", "ceres"},
          {"scene", "usb"},
          {"object", "plug"},
          {"status", "ok"},
          {"success", true},
          {"t_err_um", 2.0},
          {"r_err_deg", 0.01},
          {"false_accept", false},
          {"expect", "pose"},
          {"timing", {{"time_s", 0.5}, {"peak_rss_mb", 10.0}}}};
}

io::Json header(const std::string& shard, size_t trials) {
  return {{"format", "laserfit.bench/1"},
          {"benchmark", "quick"},
          {"file", "benchmarks/quick.yaml"},
          {"digest", "0a0b0c0d"},
          {"seed", 1},
          {"methods", {"ceres"}},
          {"repetitions", io::Json::array()},
          {"scenes", io::Json::array()},
          {"thresholds", ""},
          {"build", "laserfit test"},
          {"trials_selected", 10},
          {"trials_total", 10},
          {"shard", shard},
          {"trials", trials}};
}

// Shard i of n of a 10-trial run: its trials k = i mod n, one record each.
std::string write_shard(const test::TempDir& dir, int i, int n, io::Json over = {}) {
  const std::string d = dir / ("s" + std::to_string(i));
  fs::create_directories(d);
  std::vector<io::Json> rs;
  for (int t = i; t < 10; t += n) rs.push_back(record(t));
  io::Json run = header(std::to_string(i) + "/" + std::to_string(n), rs.size());
  if (!over.is_null()) run.update(over);
  bench::write_results(d, rs, run);
  return d;
}

std::string merge_error(const std::vector<std::string>& dirs, const std::string& out) {
  try {
    bench::merge_runs(dirs, out);
  } catch (const Error& e) {
    EXPECT_FALSE(fs::exists(out + "/results.jsonl"));
    return e.what();
  }
  return "";
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST(Merge, SixteenShardsOfTenTrialsMergeIntoOneRunDerivedFromTheRecords) {
  test::TempDir dir;
  std::vector<std::string> shards;
  for (int i = 0; i < 16; ++i) shards.push_back(write_shard(dir, i, 16));  // 6 empty shards
  const auto sum = bench::merge_runs(shards, dir / "m");
  EXPECT_EQ(sum.trials, 10u);
  EXPECT_EQ(sum.records, 10u);
  const auto rs = bench::read_results(dir / "m/results.jsonl");
  for (int t = 0; t < 10; ++t) EXPECT_EQ(rs[t].at("trial"), t);  // sorted by trial
  const io::Json run = io::read_json(dir / "m/run.json");
  EXPECT_EQ(run.at("trials"), 10);
  EXPECT_EQ(run.at("records"), 10);
  EXPECT_EQ(run.at("shard"), "0/1");
  EXPECT_FALSE(run.contains("jobs"));  // nothing copied that the records do not say
  // The merged run is itself a valid one-shard run.
  EXPECT_EQ(bench::merge_runs({dir / "m"}, dir / "m2").records, 10u);
}

TEST(Merge, RefusesEveryShardThatIsNotPartOfExactlyOneRun) {
  test::TempDir dir;
  const std::string s0 = write_shard(dir, 0, 2), s1 = write_shard(dir, 1, 2);
  // A lost line: the CRC-32 in run.json no longer matches.
  const std::string text = test::read_bytes(s1 + "/results.jsonl");
  test::write_text(s1 + "/results.jsonl", text.substr(0, text.rfind('\n', text.size() - 2) + 1));
  EXPECT_TRUE(has(merge_error({s0, s1}, dir / "m"), "differs from its run.json (CRC-32)"));
  write_shard(dir, 1, 2);
  // run.json's count disagreeing with its own records.
  io::Json run = io::read_json(s1 + "/run.json");
  run["trials"] = 4;
  test::write_text(s1 + "/run.json", run.dump());
  EXPECT_TRUE(has(merge_error({s0, s1}, dir / "m"), "5 trials, run.json says 4"));
  write_shard(dir, 1, 2);
  // Foreign shards: another selection, another benchmark content, another build.
  for (const io::Json& over :
       {io::Json{{"scenes", {"needle"}}}, io::Json{{"digest", "ffffffff"}},
        io::Json{{"build", "laserfit other"}}, io::Json{{"methods", {"gicp"}}}}) {
    write_shard(dir, 1, 2, over);
    EXPECT_TRUE(has(merge_error({s0, s1}, dir / "m"), "not shards of one run")) << over.dump();
  }
  write_shard(dir, 1, 2);
  EXPECT_TRUE(has(merge_error({s0}, dir / "m"), "1 of 2 shards given"));
  EXPECT_TRUE(has(merge_error({s0, s0}, dir / "m"), "given twice"));
  // A shard that holds fewer trials than the run selects (selection claims 12).
  write_shard(dir, 0, 2, {{"trials_selected", 12}});
  write_shard(dir, 1, 2, {{"trials_selected", 12}});
  EXPECT_TRUE(
      has(merge_error({s0, s1}, dir / "m"), "the shards hold 10 trials, the run selects 12"));
  // The path a benchmark was named by is not its identity.
  write_shard(dir, 0, 2, {{"file", "/abs/benchmarks/quick.yaml"}});
  write_shard(dir, 1, 2);
  EXPECT_EQ(merge_error({s0, s1}, dir / "m"), "");
}

TEST(Merge, ASecondWriterIntoARunsDirectoryIsRefused) {
  test::TempDir dir;
  fs::create_directories(dir / "run");
  const int fd = ::open((dir / "run/.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // as a running laserfit bench holds it
  bench::RunSettings s;
  s.out_dir = dir / "run";
  s.progress = false;
  bench::Benchmark b;
  b.name = "b";
  try {
    bench::run_benchmark(b, s);
    ADD_FAILURE() << "ran beside the lock holder";
  } catch (const Error& e) {
    EXPECT_TRUE(has(e.what(), "another laserfit bench is writing here")) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "run/journal.jsonl"));
  ::close(fd);
}

TEST(Manifest, AFilePathMustStayInsideTheDataset) {
  EXPECT_EQ(bench::manifest_path("m.json", "scans/0.pcd"), "scans/0.pcd");
  for (const char* bad : {"../x.pcd", "/etc/passwd", "scans/../../x", ""})
    EXPECT_THROW(bench::manifest_path("m.json", bad), Error) << bad;
}

// Campaign records are kept as .jsonl.xz in reports/: read as they are, and a damaged archive is
// one error naming it, never a silently shorter list.
TEST(Results, XzCompressedRecordsReadAsThePlainFile) {
  test::TempDir dir;
  std::string text;
  for (int t = 0; t < 500; ++t) text += record(t).dump() + "\n";
  test::write_text(dir / "r.jsonl", text);
  {
    std::ofstream file(dir / "r.jsonl.xz", std::ios::binary);
    boost::iostreams::filtering_ostream out;
    out.push(boost::iostreams::lzma_compressor());
    out.push(file);
    out << text;
  }
  const auto plain = bench::read_results(dir / "r.jsonl");
  EXPECT_EQ(bench::read_results(dir / "r.jsonl.xz"), plain);
  EXPECT_EQ(plain.size(), 500u);
  const std::string xz = test::read_bytes(dir / "r.jsonl.xz");
  std::string flipped = xz;
  flipped[xz.size() / 2] ^= 0x40;
  test::write_text(dir / "flipped.jsonl.xz", flipped);
  test::write_text(dir / "cut.jsonl.xz", xz.substr(0, xz.size() / 2));
  for (const char* f : {"flipped.jsonl.xz", "cut.jsonl.xz"}) {
    try {
      const auto r = bench::read_results(dir / f);
      ADD_FAILURE() << f << " read as " << r.size() << " records";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
}
