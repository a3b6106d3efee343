// Coordinate search: for each parameter in turn, try its candidates with the others at their
// current best and keep a candidate only if it scores strictly better on the training split
// (ties keep the default, so an untouched value means "no evidence to move it").
#include "laserfit/bench/tune.hpp"

#include <iostream>
#include <map>
#include <sstream>

#include "laserfit/bench/checksum.hpp"
#include "laserfit/bench/trial.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/parallel.hpp"
#include "laserfit/metrics/stats.hpp"

namespace laserfit::bench {

bool Score::better_than(const Score& o) const {
  const double fa = records ? double(false_accepts) / records : 0,
               ofa = o.records ? double(o.false_accepts) / o.records : 0;
  if (fa != ofa) return fa < ofa;
  if (success_rate() != o.success_rate()) return success_rate() > o.success_rate();
  if (median_t_um < 0.95 * o.median_t_um) return true;
  if (median_t_um > 1.05 * o.median_t_um) return false;
  return attempts < 0.9 * o.attempts;
}

const std::vector<std::pair<std::string, std::vector<double>>>& tunable_params() {
  static const std::vector<std::pair<std::string, std::vector<double>>> p = {
      {"rho_rot", {15, 30, 45}},
      {"rho_icp", {0.02, 0.05, 0.1}},
      {"max_rmse", {0.3, 0.5, 0.8}},
      {"min_overlap", {0.2, 0.3, 0.5}},
      {"voxel_scale", {0.75, 1.0, 1.5}},
      {"feature_radius", {4, 6, 9}},
      {"ransac_iterations", {2000, 10000, 50000}},
      {"max_correspondence", {1.5, 2.0, 3.0}}};
  return p;
}

namespace {

double& param(registration::Thresholds& t, const std::string& name, double& iterations) {
  if (name == "rho_rot") return t.rho_rot_deg;
  if (name == "rho_icp") return t.rho_icp_vox2;
  if (name == "max_rmse") return t.max_rmse_vox;
  if (name == "min_overlap") return t.min_overlap;
  if (name == "voxel_scale") return t.voxel_scale;
  if (name == "feature_radius") return t.feature_radius_vox;
  if (name == "ransac_iterations") return iterations;
  if (name == "max_correspondence") return t.max_correspondence_vox;
  throw Error("unknown tuning parameter '" + name + "'");
}

void set(registration::Thresholds& t, const std::string& name, double v) {
  double it = t.ransac_iterations;
  param(t, name, it) = v;
  t.ransac_iterations = int(it);
}

double get(registration::Thresholds t, const std::string& name) {
  double it = t.ransac_iterations;
  return param(t, name, it);
}

// The trials of a split with their scans, simulated once and kept for every evaluation.
struct Split {
  std::vector<Trial> trials;
  std::vector<TrialInput> inputs;
};

Split make_split(const Benchmark& b, const std::map<int, PreparedScene>& scenes,
                 const std::vector<int>& reps, int jobs) {
  Split s;
  for (const auto& t : enumerate_trials(b))
    for (int r : reps)
      if (t.repetition == r) s.trials.push_back(t);
  s.inputs.resize(s.trials.size());
  parallel_for(s.trials.size(), jobs, [&](size_t i) {
    s.inputs[i] = trial_input(b, scenes.at(s.trials[i].scene), s.trials[i]);
  });
  return s;
}

Score evaluate(const Benchmark& b, const std::map<int, PreparedScene>& scenes, const Split& split,
               const registration::Thresholds& th, registration::Method method, int jobs) {
  TrialOptions o;
  o.methods = {method};
  o.thresholds = &th;
  std::vector<std::vector<io::Json>> recs(split.trials.size());
  parallel_for(split.trials.size(), jobs, [&](size_t i) {
    recs[i] = run_trial(b, scenes.at(split.trials[i].scene), split.trials[i], split.inputs[i], o);
  });
  Score s;
  std::vector<double> t, time;
  for (const auto& rs : recs)
    for (const auto& r : rs) {
      ++s.records;
      s.successes += r.at("success").get<bool>();
      s.false_accepts += r.at("false_accept").get<bool>();
      s.attempts += r.at("attempts").get<int>();
      if (r.at("status") != "failed" && r.at("expect") == "pose") t.push_back(r.at("t_err_um"));
      time.push_back(r.at("timing").at("time_s"));
    }
  s.median_t_um = t.empty() ? 0 : metrics::median(t);
  s.median_time_s = metrics::median(time);
  return s;
}

io::Json score_json(const Score& s) {
  return {{"records", s.records},
          {"success_rate", s.success_rate()},
          {"false_accepts", s.false_accepts},
          {"attempts", s.attempts},
          {"median_t_err_um", s.median_t_um},
          {"median_time_s", s.median_time_s}};
}

std::string range_text(const std::vector<int>& r) {
  return r.empty() ? "" : std::to_string(r.front()) + ":" + std::to_string(r.back() + 1);
}

}  // namespace

TuneResult tune(const Benchmark& b, const TuneSettings& s) {
  if (s.train.empty() || s.test.empty())
    throw Error("tuning needs a training and a held-out split");
  for (int r : s.train)
    for (int q : s.test)
      if (r == q)
        throw Error("the training and held-out splits share repetition " + std::to_string(r));
  for (int r : s.train)
    if (r >= b.trials)
      throw Error(b.file, "no repetition " + std::to_string(r) +
                              " (trials: " + std::to_string(b.trials) + ")");
  for (int r : s.test)
    if (r >= b.trials)
      throw Error(b.file, "no repetition " + std::to_string(r) +
                              " (trials: " + std::to_string(b.trials) + ")");
  std::vector<std::string> names = s.params;
  if (names.empty())
    for (const auto& p : tunable_params()) names.push_back(p.first);
  std::map<int, PreparedScene> scenes;
  for (size_t i = 0; i < b.scenes.size(); ++i) scenes.emplace(int(i), prepare_scene(b, int(i)));
  const int jobs = std::max(1, s.jobs);
  const Split train = make_split(b, scenes, s.train, jobs);

  TuneResult out;
  registration::Thresholds best;
  best.method = s.method;
  for (const auto& sc : b.scenes)
    for (const auto& t : sc.targets)
      if (t.voxel_mm > 0) best.voxel_mm[t.object] = t.voxel_mm;
  auto log = [&](const std::string& what, const Score& sc) {
    if (s.progress)
      std::cerr << "tune: " << what << ": success " << sc.success_rate() * 100
                << " %, false accepts " << sc.false_accepts << ", median " << sc.median_t_um
                << " um, " << sc.attempts << " attempts, " << sc.median_time_s << " s\n";
  };
  Score best_score = evaluate(b, scenes, train, best, s.method, jobs);
  out.baseline_train = best_score;
  out.history.push_back({{"param", "defaults"}, {"train", score_json(best_score)}});
  log("defaults", best_score);
  for (const auto& name : names) {
    const auto it = std::find_if(tunable_params().begin(), tunable_params().end(),
                                 [&](const auto& p) { return p.first == name; });
    if (it == tunable_params().end()) throw Error("unknown tuning parameter '" + name + "'");
    const double current = get(best, name);
    for (double v : it->second) {
      if (v == current) continue;
      registration::Thresholds cand = best;
      set(cand, name, v);
      const Score sc = evaluate(b, scenes, train, cand, s.method, jobs);
      out.history.push_back({{"param", name}, {"value", v}, {"train", score_json(sc)}});
      std::ostringstream what;
      what << name << " = " << v;
      log(what.str(), sc);
      if (sc.better_than(best_score)) best = cand, best_score = sc;
    }
  }
  out.best_train = best_score;
  const Split test = make_split(b, scenes, s.test, jobs);
  out.held_out = evaluate(b, scenes, test, best, s.method, jobs);
  registration::Thresholds defaults;
  defaults.method = s.method, defaults.voxel_mm = best.voxel_mm;
  const bool unchanged = thresholds_yaml(defaults) == thresholds_yaml(best);
  out.baseline_held_out =
      unchanged ? out.held_out : evaluate(b, scenes, test, defaults, s.method, jobs);
  log("held out, tuned", out.held_out);
  log("held out, defaults", out.baseline_held_out);
  best.benchmark = b.name, best.benchmark_file = b.file,
  best.benchmark_digest = hex32(uint32_t(b.digest));
  best.seed = b.seed, best.train = range_text(s.train), best.test = range_text(s.test);
  best.held_out_registrations = out.held_out.records,
  best.held_out_false_accepts = out.held_out.false_accepts;
  best.held_out_success_rate = out.held_out.success_rate(),
  best.held_out_median_t_um = out.held_out.median_t_um;
  out.thresholds = best;
  return out;
}

}  // namespace laserfit::bench
