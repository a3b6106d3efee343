#pragma once
// The benchmark runner: every (trial x target x method) of a benchmark (or of one shard of it), in
// parallel, each trial's records journaled as it completes so an interrupted run resumes without
// repeating or losing trials; at the end DIR/results.jsonl (sorted by trial: the same bytes
// whatever the job count, apart from each record's "timing"), DIR/summary.csv and DIR/run.json,
// all written atomically.
#include <string>
#include <vector>

#include "laserfit/bench/spec.hpp"
#include "laserfit/bench/trial.hpp"
#include "laserfit/io/json.hpp"

namespace laserfit::bench {

struct RunSettings {
  std::vector<registration::Method> methods;  // empty: the benchmark's own list
  Shard shard;
  std::string out_dir;                // results.jsonl, summary.csv, run.json, overlays/
  std::string dataset_dir;            // non-empty: read scans from a generated dataset
  std::string thresholds_file;        // non-empty: tuned thresholds on top of each method
  int jobs = 1;                       // trials in parallel (1: per-trial peak memory)
  std::string jobs_source;            // where `jobs` came from (cpu_budget's source), for run.json
  std::vector<int> only_repetitions;  // non-empty: only these repetitions (tuning splits)
  std::vector<std::string> only_scenes;  // non-empty: only these scenes (by name)
  bool overlays = true;                  // first trial of each scene: overlay clouds
  bool progress = true;                  // progress on stderr (a bar on a terminal)
};

struct RunSummary {
  size_t trials = 0, resumed = 0, records = 0;
  double wall_s = 0, trials_per_s = 0;
};

RunSummary run_benchmark(const Benchmark& b, const RunSettings& s);

// Combines the result directories of the shards 0..N-1 of one benchmark into `out_dir`. Refuses
// anything that is not exactly one run: a missing, repeated or foreign shard (benchmark content,
// methods, scenes, repetitions, thresholds or build differ), a shard whose results.jsonl does not
// match its own run.json (record count, CRC-32, trials), a record in the wrong shard, or shards
// that do not add up to the run's selection. An empty shard is a shard. The merged run.json is
// derived from the merged records. The merge equals a single run of all trials.
RunSummary merge_runs(const std::vector<std::string>& dirs, const std::string& out_dir);

// What makes two runs (or a journal and a run) the same run: every field of run.json's header
// except where it was written from (the benchmark's path spelling, the job count).
io::Json run_identity(const io::Json& run);

// results.jsonl <-> records; records sorted by (trial, object order, method order) as written.
// `allow_empty`: a shard with no trials has an empty results.jsonl.
std::vector<io::Json> read_results(const std::string& path, bool allow_empty = false);
void write_results(const std::string& dir, const std::vector<io::Json>& records,
                   const io::Json& run);

// The figures of a group of records: success, false accepts, ambiguous and failed counts, the
// errors of the poses returned (status not failed, a pose expected), time and peak memory.
// A target with fewer labelled scan points than the thin-part detector's smallest candidate
// cannot be registered by any method: "not visible". A record whose scan does not determine the
// pose (see "determinable") is a miss for the success rate, and counted apart as well.
inline const long kMinVisiblePoints = registration::ThinSettings{}.min_points;
// Does the scan determine the pose? The refinement from the truth (the record's "determinable")
// and the target in view: with the target absent, that refinement holds still on whatever lies
// near the truth (a needle's eye next to a thread tip the sweep missed) and passes for an
// answer. visible_points < 0: a scan without labels; no "determinable": an older run's record.
inline bool in_view(long visible_points) {
  return visible_points < 0 || visible_points >= kMinVisiblePoints;
}
inline bool determinable(const io::Json& record) {
  return record.value("determinable", true) && in_view(record.value("visible_points", -1L));
}
struct GroupStats {
  size_t records = 0;
  int successes = 0, false_accepts = 0, ambiguous = 0, failed = 0;
  int not_visible = 0;  // unsuccessful with the target (nearly) absent from the scan
  // Records whose scan determines the pose (refined from the truth, the default method succeeds;
  // records of older runs without the check count as determinable) and their successes.
  int determinable = 0, determinable_successes = 0;
  double t_median_um = 0, t_p95_um = 0, r_median_deg = 0, r_p95_deg = 0;
  double time_median_s = 0, time_p95_s = 0, peak_rss_mb = 0;
  double success_rate() const { return records ? double(successes) / double(records) : 0; }
  double determinable_success_rate() const {
    return determinable ? double(determinable_successes) / double(determinable) : 0;
  }
};
GroupStats group_stats(const std::vector<const io::Json*>& records);

// What a record says about its scan rather than its method ("visible_points", "determinable")
// copied onto the records of the same (benchmark, trial, object) that lack it, such as the Open3D
// baseline's, which registers laserfit's scans but cannot run the check at the truth. A record
// filled so names its donor's method in "scan_facts_from". Returns how many were filled.
size_t share_scan_facts(std::vector<io::Json>& records);

// Per (method, scene, object) and per method overall: success rate, false accepts, ambiguous,
// failed, not visible, determinable records and their success rate, median / p95 errors over
// the poses returned (status not failed), time, peak memory.
std::string summary_csv(const std::vector<io::Json>& records);

}  // namespace laserfit::bench
