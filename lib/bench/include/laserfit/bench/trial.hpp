#pragma once
// Trials of a benchmark: a fixed, seed-determined list (scene x condition cell x repetition), the
// scan each one scans (simulated in memory or read back from a generated dataset — the same
// bytes), and the records its registrations produce.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "laserfit/bench/spec.hpp"
#include "laserfit/core/cloud.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/registration/thresholds.hpp"
#include "laserfit/scan/scanner.hpp"

namespace laserfit::bench {

struct Trial {
  int index = 0;       // position in the benchmark's list (stable: scene, cell, repetition)
  int scene = 0;       // into Benchmark::scenes
  int cell = 0;        // grid cell (random mode: 0)
  int repetition = 0;  // 0 .. trials-1 within its cell
  Conditions conditions;
  uint64_t seed = 0;  // the trial's own seed: perturbation, scan noise, registration
  int image = -1;     // recorded scenes: the scan's image id (its seed derives from it)
};
std::vector<Trial> enumerate_trials(const Benchmark& b);
// The trials of some repetitions and some scenes (by name; empty: all), in enumerate order.
std::vector<Trial> select_trials(const Benchmark& b, const std::vector<int>& repetitions,
                                 const std::vector<std::string>& scenes);

// Shards: trial k belongs to shard k mod n (interleaved, so every shard gets every scene).
struct Shard {
  int i = 0, n = 1;
  bool contains(const Trial& t) const { return t.index % n == i; }
  std::string text() const { return std::to_string(i) + "/" + std::to_string(n); }
};
Shard parse_shard(const std::string& text);  // "i/N", 0 <= i < N

// A scene of the benchmark, loaded once, with its targets' reference clouds.
struct PreparedScene {
  scan::ScanScene scene;
  std::vector<int> object;              // per target: index into scene.objects
  std::vector<PointCloud> reference;    // per target
  std::vector<TriMesh> reference_mesh;  // per target: what the reference is sampled from
  std::vector<std::vector<Eigen::Vector3f>> model;  // per target: mesh vertices (MSSD)
  std::vector<Eigen::Vector3d>
      pivot;  // per target: what the true pose turns about (object frame, mm)
};
PreparedScene prepare_scene(const Benchmark& b, int scene);

// What a trial's registrations see and are scored against.
struct TrialInput {
  PointCloud scan;                 // organized, base frame, labels = scene object
  std::vector<Pose> truth, prior;  // per target: T_scan_object (ground truth) and the prior
  bool has_prior = true;           // false: prior: none, or no scene_prior.json
  uint64_t scan_seed = 0;
  size_t scan_points = 0;  // valid points
};
TrialInput simulate_trial(const Benchmark& b, const PreparedScene& p, const Trial& t);
// simulate_trial, or a recorded scene's scan read from its folder.
TrialInput trial_input(const Benchmark& b, const PreparedScene& p, const Trial& t);
// The ground-truth file of a dataset trial: conditions, seeds, and per target its scan label,
// reference file, symmetry, true and prior poses.
io::Json input_json(const Benchmark& b, const PreparedScene& p, const Trial& t,
                    const TrialInput& in);
TrialInput read_trial(const PreparedScene& p, const std::string& scan_pcd,
                      const std::string& gt_json);

// Registration settings of a named method (paper: PCL SampleConsensusPrerejective + rho_rot on
// its result + PCL ICP, no prior pose; the others: rho_rot inside RANSAC, the prior as the first
// hypothesis, the named refiner), with tuned thresholds on top when given. An `ok` promises the
// benchmark's tolerance: it is the trust's pinning limit (TrustSettings::max_sigma_mm, _deg).
registration::RegistrationSettings method_settings(const Benchmark& b, registration::Method method,
                                                   const Target& target,
                                                   const registration::Thresholds* thresholds);

// Can this scan determine target k's pose at all? The default method refined from the true pose,
// against what the scanner sees of the part there (see evaluate.cpp): when even that is no success
// by the benchmark's rule, no method can answer `ok` and be right.
struct AtTruth {
  bool determinable = false;
  std::string status, reason;  // of the refinement from the truth
};
AtTruth at_truth(const Benchmark& b, const PreparedScene& p, const Trial& t, const TrialInput& in,
                 size_t k, const registration::Thresholds* thresholds);

struct TrialOptions {
  std::vector<registration::Method> methods;
  const registration::Thresholds* thresholds = nullptr;
  std::string overlay_dir;  // non-empty: write scan + registered reference clouds here
};
// One JSON record per (target, method) — see docs in bench/README: errors, status, success,
// the fit statistics, and a "timing" object (the only part that differs between runs).
std::vector<io::Json> run_trial(const Benchmark& b, const PreparedScene& p, const Trial& t,
                                const TrialInput& in, const TrialOptions& o);

}  // namespace laserfit::bench
