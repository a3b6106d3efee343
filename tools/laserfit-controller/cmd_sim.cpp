// laserfit-controller sim --cell C.yaml --thresholds T.yaml --strategy ic1,ic2,laser [--trials N]
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>

#include "commands.hpp"
#include "laserfit/controller/sim.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/parallel.hpp"

namespace laserfit::ctl {
namespace {

struct Options {
  std::string cell, thresholds, strategies = "ic1,ic2,laser", out, dump;
  int trials = 0, first = 0, jobs = 1;
  uint64_t seed = 1;
  bool json = false, quiet = false, verify_each = false, forget = false;
};

// The trials, each arm pair's in order on one thread (a trial starts from what the pair's earlier
// trials of the same strategy taught), the pairs in parallel: the same outcomes for any --jobs.
std::vector<controller::Outcome> run_trials(const Options& o, const cell::CellSettings& cs,
                                            const controller::ControllerSettings& s,
                                            const std::vector<controller::Strategy>& strategies,
                                            int trials) {
  using namespace controller;
  Campaign campaign(cs, s, o.seed);
  std::map<int, std::vector<int>> pairs;  // robot -> its trials, in order
  for (int i = o.first; i < o.first + trials; ++i) {
    const TrialPlan t = plan_trial(cs, o.seed, i);
    campaign.prepare(t);
    pairs[t.robot].push_back(i);
  }
  std::vector<std::vector<int>> chains;
  for (auto& [robot, c] : pairs) chains.push_back(c);
  std::vector<Outcome> out(trials * strategies.size());
  size_t done = 0;
  std::mutex m;
  parallel_for(chains.size(), o.jobs, [&](size_t c) {
    std::vector<MotionErrorModel> learned(strategies.size(), MotionErrorModel(s.learning));
    for (const int i : chains[c])
      for (size_t k = 0; k < strategies.size(); ++k) {
        const TrialPlan t = plan_trial(cs, o.seed, i);
        MotionErrorModel fresh(s.learning);
        out[(i - o.first) * strategies.size() + k] =
            run_insertion(campaign.cell(t.robot), campaign.setup(t.robot, t.setting), strategies[k],
                          t.start, t.seed, s, o.forget ? &fresh : &learned[k]);
        std::lock_guard<std::mutex> l(m);
        ++done;
        if (!o.quiet) std::cerr << "\rsim: " << done << "/" << out.size() << std::flush;
      }
  });
  if (!o.quiet) std::cerr << "\r";
  return out;
}

int run(const Options& o) {
  using namespace controller;
  const cell::CellSettings cs = cell::load_cell(o.cell);
  ControllerSettings s = settings_for(cs);
  s.thresholds = registration::load_thresholds(o.thresholds);
  s.fold = !o.verify_each;
  s.dump_dir = o.dump;
  if (!o.dump.empty()) std::filesystem::create_directories(o.dump);
  std::vector<Strategy> strategies;
  {
    std::stringstream in(o.strategies);
    for (std::string x; std::getline(in, x, ',');)
      if (!x.empty()) strategies.push_back(parse_enum<Strategy>(x));
  }
  const int trials = o.trials > 0 ? o.trials : int(cs.target_poses.size()) * cs.start_configs;
  if (o.first < 0) throw Error("--first must be >= 0");
  const std::vector<Outcome> out = run_trials(o, cs, s, strategies, trials);
  std::map<std::string, std::pair<int, int>> rate;  // strategy -> (successes, trials)
  std::map<std::string, std::map<int, std::pair<int, int>>> by_setting;
  std::string lines;
  for (const auto& x : out) {
    auto& r = rate[name_of(x.strategy)];
    r.first += x.success, r.second += 1;
    auto& b = by_setting[name_of(x.strategy)][x.setting];
    b.first += x.success, b.second += 1;
    lines += outcome_json(x).dump() + "\n";
  }
  if (!o.out.empty()) write_file_atomic(o.out, lines);
  io::Json summary = {{"cell", o.cell},
                      {"task", cs.task},
                      {"seed", o.seed},
                      {"first", o.first},
                      {"trials", trials},
                      {"thresholds", o.thresholds},
                      {"strategies", io::Json::object()}};
  std::ostringstream h;
  h << cs.task << " cell, " << trials << " trials per strategy from trial " << o.first << " (seed "
    << o.seed << "):\n";
  for (const auto& [name, r] : rate) {
    io::Json per = io::Json::array();
    for (const auto& [k, b] : by_setting[name]) per.push_back(double(b.first) / b.second);
    summary["strategies"][name] = {{"success_rate", double(r.first) / r.second},
                                   {"successes", r.first},
                                   {"trials", r.second},
                                   {"per_setting", per}};
    h << "  " << name << ": " << r.first << "/" << r.second << " = " << 100.0 * r.first / r.second
      << " %\n";
  }
  if (o.json)
    std::cout << summary.dump(2) << "\n";
  else
    std::cout << h.str();
  return 0;
}

}  // namespace

Command add_sim(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand("sim", "Run the controller against the simulated dual-arm cell");
  app->add_option("--cell", o->cell, "cell definition (YAML, cells/*.yaml)")->required();
  app->add_option("--thresholds", o->thresholds, "tuned registration thresholds (laserfit tune)")
      ->required();
  app->add_option("--strategy", o->strategies,
                  "comma-separated: ic1, ic2 (proprioception only), laser, "
                  "laser_pose (position + orientation)")
      ->capture_default_str();
  app->add_option("--trials", o->trials,
                  "trials per strategy (default: settings x start configurations; "
                  "beyond that, new seeded arm pairs)");
  app->add_option("--first", o->first,
                  "index of the first trial (run trials first .. first + trials - 1)")
      ->capture_default_str();
  app->add_option("--seed", o->seed, "seed of the arms' errors, noise and scans")
      ->capture_default_str();
  app->add_option("--jobs", o->jobs, "arm pairs in parallel (each pair's trials run in order)")
      ->capture_default_str();
  app->add_option("-o,--output,--out", o->out,
                  "write every trial's outcome and decision log here (JSON Lines)");
  app->add_option("--dump", o->dump,
                  "write every scan and the reference clouds here (to look at them)");
  add_verify_each_flag(*app, o->verify_each);
  add_forget_flag(*app, o->forget);
  app->add_flag("--quiet", o->quiet, "no progress on stderr");
  app->add_flag("--json", o->json, "machine-readable summary on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::ctl
