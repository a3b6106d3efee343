#pragma once
// Threshold tuning (replaces the paper's "empirically" chosen rho_ICP and rho_rot): a coordinate
// search over the registration parameters that matter, scored on a training split of a
// benchmark's repetitions, the winner measured on the held-out split and written as a
// thresholds file (registration/thresholds.hpp) that the controller reads.
#include <string>
#include <vector>

#include "laserfit/bench/spec.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/registration/thresholds.hpp"

namespace laserfit::bench {

struct Score {
  int records = 0, successes = 0, false_accepts = 0;
  int attempts = 0;  // RANSAC + refinement rounds, summed: the work done
  double median_t_um = 0, median_time_s = 0;
  double success_rate() const { return records ? double(successes) / records : 0; }
  // Fewer false accepts first (a wrong `ok` makes the robot miss), then more successes, then a
  // clearly lower median error (5 %), then clearly less work (10 % fewer attempts). Only
  // deterministic quantities: wall time under parallel load is too noisy to choose by.
  bool better_than(const Score& o) const;
};

struct TuneSettings {
  registration::Method method = registration::Method::Ceres;
  std::vector<int> train, test;     // repetitions of every cell
  std::vector<std::string> params;  // empty: all of tunable_params()
  int jobs = 1;
  bool progress = true;
};

struct TuneResult {
  registration::Thresholds thresholds;  // with provenance and held-out figures
  Score baseline_train, best_train, held_out, baseline_held_out;
  io::Json history = io::Json::array();  // every evaluation: parameter, value, score
};

// Parameter names (Thresholds fields) and the candidate values the search tries for each.
const std::vector<std::pair<std::string, std::vector<double>>>& tunable_params();

TuneResult tune(const Benchmark& b, const TuneSettings& s);

}  // namespace laserfit::bench
