// results.jsonl / summary.csv / run.json, and merging the shards of one benchmark.
#include <filesystem>
#include <fstream>
#include <set>

#include "laserfit/bench/runner.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::bench {

std::vector<io::Json> read_results(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path, "cannot read the file");
  std::vector<io::Json> out;
  size_t n = 0;
  for (std::string line; std::getline(in, line);) {
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
  if (out.empty()) throw Error(path, "no records");
  return out;
}

void write_results(const std::string& dir, const std::vector<io::Json>& records,
                   const io::Json& run) {
  std::string text;
  for (const auto& r : records) text += r.dump() + "\n";
  // The three files are committed together at the end; results.jsonl last, as the marker of a
  // complete run.
  write_file_atomic(dir + "/summary.csv", summary_csv(records));
  write_file_atomic(dir + "/run.json", run.dump(2) + "\n");
  write_file_atomic(dir + "/results.jsonl", text);
}

RunSummary merge_runs(const std::vector<std::string>& dirs, const std::string& out_dir) {
  namespace fs = std::filesystem;
  if (dirs.empty()) throw Error("merge: no result directories given");
  std::map<int, std::vector<io::Json>> trials;  // trial -> records, in order
  std::set<std::string> shards;
  io::Json first;
  int n = 0;
  double wall = 0;
  for (const auto& d : dirs) {
    const io::Json run = io::read_json(d + "/run.json");
    const std::string shard = run.value("shard", "");
    if (first.is_null()) {
      first = run;
      n = std::stoi(shard.substr(shard.find('/') + 1));
    }
    for (const char* k : {"benchmark", "digest", "methods", "thresholds", "repetitions", "dataset"})
      if (run.value(k, io::Json()) != first.value(k, io::Json()))
        throw Error(d + "/run.json", std::string("'") + k + "' differs from " + dirs[0] +
                                         " (not shards of one run)");
    if (std::stoi(shard.substr(shard.find('/') + 1)) != n)
      throw Error(d + "/run.json", "shard count differs");
    if (!shards.insert(shard).second)
      throw Error(d + "/run.json", "shard " + shard + " given twice");
    wall = std::max(wall, run.value("wall_s", 0.0));
    for (auto& r : read_results(d + "/results.jsonl")) {
      const int t = r.at("trial");
      trials[t].push_back(std::move(r));
    }
    if (fs::is_directory(d + "/overlays")) {
      fs::create_directories(out_dir + "/overlays");
      for (const auto& e : fs::directory_iterator(d + "/overlays"))
        fs::copy_file(e.path(), out_dir + "/overlays/" + e.path().filename().string(),
                      fs::copy_options::overwrite_existing);
    }
  }
  if (int(shards.size()) != n)
    throw Error("merge: " + std::to_string(shards.size()) + " of " + std::to_string(n) +
                " shards given");
  std::vector<io::Json> records;
  for (auto& [t, rs] : trials)
    for (auto& r : rs) records.push_back(std::move(r));
  fs::create_directories(out_dir);
  io::Json run = first;
  run["shard"] = "0/1", run["merged_from"] = dirs, run["records"] = records.size();
  run["trials"] = trials.size(), run["wall_s"] = wall, run.erase("trials_per_s");
  write_results(out_dir, records, run);
  RunSummary s;
  s.trials = trials.size(), s.records = records.size(), s.wall_s = wall;
  return s;
}

}  // namespace laserfit::bench
