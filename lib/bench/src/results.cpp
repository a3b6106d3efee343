// results.jsonl / summary.csv / run.json, and merging the shards of one benchmark.
#include <boost/iostreams/filter/lzma.hpp>
#include <boost/iostreams/filtering_stream.hpp>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "laserfit/bench/checksum.hpp"
#include "laserfit/bench/runner.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::bench {

namespace {

// Campaign records are kept xz-compressed in reports/ (docs: reports/README.md), and read as
// they are: a .xz file is decompressed on the fly.
std::vector<std::string> record_lines(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(path, "cannot read the file");
  boost::iostreams::filtering_istream in;
  const bool xz = path.size() > 3 && path.compare(path.size() - 3, 3, ".xz") == 0;
  if (xz) in.push(boost::iostreams::lzma_decompressor());
  in.push(file);
  in.exceptions(std::ios::badbit);  // a decoding error throws instead of ending the file early
  std::vector<std::string> lines;
  try {
    for (std::string line; std::getline(in, line);) lines.push_back(std::move(line));
  } catch (const std::exception& e) {  // boost's lzma_error: a corrupt or cut .xz file
    throw Error(path, std::string("not a readable .xz file (") + e.what() + ")");
  }
  return lines;
}

}  // namespace

std::vector<io::Json> read_results(const std::string& path, bool allow_empty) {
  std::vector<io::Json> out;
  size_t n = 0;
  for (const std::string& line : record_lines(path)) {
    ++n;
    if (line.empty()) continue;
    try {
      out.push_back(io::Json::parse(line));
      for (const char* k :
           {"trial", "method", "scene", "object", "status", "success", "t_err_um", "timing"})
        if (!out.back().contains(k)) throw Error(std::string("no '") + k + "'");
    } catch (const std::exception& e) {
      throw Error(
          path, "line " + std::to_string(n) + ": not a laserfit result record (" + e.what() + ")");
    }
  }
  if (out.empty() && !allow_empty) throw Error(path, "no records");
  return out;
}

void write_results(const std::string& dir, const std::vector<io::Json>& records,
                   const io::Json& run) {
  std::string text;
  for (const auto& r : records) text += r.dump() + "\n";
  io::Json stamped = run;  // what merge checks a shard's results.jsonl against
  stamped["records"] = records.size(), stamped["results_crc32"] = hex32(crc32(text));
  // The three files are committed together at the end; results.jsonl last, as the marker of a
  // complete run.
  write_file_atomic(dir + "/summary.csv", summary_csv(records));
  write_file_atomic(dir + "/run.json", stamped.dump(2) + "\n");
  write_file_atomic(dir + "/results.jsonl", text);
}

io::Json run_identity(const io::Json& run) {
  io::Json id;
  for (const char* k : {"format", "benchmark", "digest", "seed", "methods", "repetitions", "scenes",
                        "thresholds", "build", "trials_selected", "trials_total"})
    id[k] = run.value(k, io::Json());
  id["shard"] = run.value("shard", io::Json());
  return id;
}

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct ShardDir {
  std::string dir;
  io::Json run;
  std::vector<io::Json> records;
  int index = 0, count = 1;
};

// One shard's directory, checked against its own run.json: the shard named, the record count
// and CRC-32 of results.jsonl, its trials all of this shard and as many as it claims.
ShardDir read_shard(const std::string& dir) {
  ShardDir s{dir, io::read_json(dir + "/run.json"), {}};
  const std::string rj = dir + "/run.json", rl = dir + "/results.jsonl";
  try {
    const auto p = bench::parse_shard(s.run.at("shard").get<std::string>());
    s.index = p.i, s.count = p.n;
    const std::string text = read_file(rl);
    if (hex32(crc32(text)) != s.run.at("results_crc32").get<std::string>())
      throw Error(rl, "differs from its run.json (CRC-32): a record was lost, added or changed");
    s.records = read_results(rl, true);
    if (s.records.size() != s.run.at("records").get<size_t>())
      throw Error(rl, std::to_string(s.records.size()) + " records, run.json says " +
                          s.run.at("records").dump());
  } catch (const io::Json::exception& e) {
    throw Error(rj, std::string("not a complete laserfit run (") + e.what() + ")");
  }
  std::set<int> trials;
  for (const auto& r : s.records) {
    const int t = r.at("trial");
    if (t % s.count != s.index)
      throw Error(rl, "trial " + std::to_string(t) + " does not belong to shard " +
                          s.run["shard"].get<std::string>());
    trials.insert(t);
  }
  if (trials.size() != s.run.value("trials", size_t(0)))
    throw Error(rl, std::to_string(trials.size()) + " trials, run.json says " +
                        s.run.value("trials", io::Json(0)).dump());
  return s;
}

}  // namespace

RunSummary merge_runs(const std::vector<std::string>& dirs, const std::string& out_dir) {
  namespace fs = std::filesystem;
  if (dirs.empty()) throw Error("merge: no result directories given");
  std::vector<ShardDir> shards;
  for (const auto& d : dirs) shards.push_back(read_shard(d));
  const io::Json id = run_identity(shards[0].run);
  std::map<int, const ShardDir*> by_index;
  for (const auto& s : shards) {
    io::Json other = run_identity(s.run), mine = id;
    other.erase("shard"), mine.erase("shard");
    for (const auto& [k, v] : mine.items())
      if (other[k] != v)
        throw Error(s.dir + "/run.json",
                    "'" + k + "' differs from " + shards[0].dir + " (not shards of one run)");
    if (s.count != shards[0].count) throw Error(s.dir + "/run.json", "shard count differs");
    if (!by_index.emplace(s.index, &s).second)
      throw Error(s.dir + "/run.json",
                  "shard " + s.run["shard"].get<std::string>() + " given twice");
  }
  if (int(by_index.size()) != shards[0].count)
    throw Error("merge: " + std::to_string(by_index.size()) + " of " +
                std::to_string(shards[0].count) + " shards given");
  std::map<int, std::vector<io::Json>> trials;  // trial -> records, in order
  double wall = 0;
  for (auto& s : shards) {
    wall = std::max(wall, s.run.value("wall_s", 0.0));
    for (auto& r : s.records) trials[r.at("trial").get<int>()].push_back(std::move(r));
  }
  const size_t selected = id.value("trials_selected", size_t(0));
  if (trials.size() != selected)
    throw Error("merge: the shards hold " + std::to_string(trials.size()) + " trials, the run " +
                "selects " + std::to_string(selected));
  std::vector<io::Json> records;
  for (auto& [t, rs] : trials)
    for (auto& r : rs) records.push_back(std::move(r));
  fs::create_directories(out_dir);
  for (const auto& s : shards)
    if (fs::is_directory(s.dir + "/overlays")) {
      fs::create_directories(out_dir + "/overlays");
      for (const auto& e : fs::directory_iterator(s.dir + "/overlays"))
        fs::copy_file(e.path(), out_dir + "/overlays/" + e.path().filename().string(),
                      fs::copy_options::overwrite_existing);
    }
  io::Json run = id;  // derived from the records, not copied from a shard
  run["file"] = shards[0].run.value("file", "");
  run["shard"] = "0/1", run["merged_from"] = dirs, run["trials"] = trials.size();
  run["wall_s"] = wall;
  write_results(out_dir, records, run);
  RunSummary sum;
  sum.trials = trials.size(), sum.records = records.size(), sum.wall_s = wall;
  return sum;
}

}  // namespace laserfit::bench
