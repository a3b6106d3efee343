// laserfit-controller run --cell-endpoint HOST:PORT --cell C.yaml --thresholds T.yaml
//   --strategy laser_pose [--trials N --first I --seed S] [-o outcomes.jsonl]
#include <iostream>
#include <map>
#include <sstream>

#include "commands.hpp"
#include "laserfit/controller/sim.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/remote/client.hpp"

namespace laserfit::ctl {
namespace {

struct Options {
  std::string endpoint, cell, thresholds, strategies = "laser_pose", out, tls_ca;
  int trials = 1, first = 0;
  uint64_t seed = 1;
  double timeout_s = 10;
  bool quiet = false, verify_each = false, forget = false;
};

int run(const Options& o) {
  using namespace controller;
  const cell::CellSettings cs = cell::load_cell(o.cell);
  ControllerSettings s = settings_for(cs);
  s.thresholds = registration::load_thresholds(o.thresholds);
  s.fold = !o.verify_each;
  std::vector<Strategy> strategies;
  std::stringstream in(o.strategies);
  for (std::string x; std::getline(in, x, ',');)
    if (!x.empty()) strategies.push_back(parse_enum<Strategy>(x));
  if (o.first < 0 || o.trials < 1) throw Error("--first must be >= 0 and --trials >= 1");
  remote::RemoteCell cell({o.endpoint, o.timeout_s, o.tls_ca});
  Campaign campaign(cs, s, o.seed);
  std::string lines;
  int inserted = 0, done = 0;
  // What each arm pair's earlier trials taught, per strategy (a real cell is one pair; a
  // simulated one changes pairs with the trial index, as sim does).
  std::map<std::pair<int, Strategy>, MotionErrorModel> learned;
  for (int i = o.first; i < o.first + o.trials; ++i)
    for (const Strategy st : strategies) {
      // The taught poses and references are the cell file's; a simulated cell is reset to the
      // same trial and must agree on where it put the arm.
      const TrialPlan t = plan_trial(cs, o.seed, i);
      campaign.prepare(t);
      if (cell.simulated()) {
        const auto [setting, start] = cell.begin_trial(o.seed, i);
        if (setting != t.setting || start != t.start)
          throw Error("cell " + o.endpoint + ": trial " + std::to_string(i) +
                      " is set up differently there (another cell file?)");
      }
      MotionErrorModel fresh(s.learning);
      auto& memory =
          o.forget ? fresh : learned.try_emplace({t.robot, st}, s.learning).first->second;
      const Outcome x =
          run_insertion(cell, campaign.cell(t.robot), campaign.setup(t.robot, t.setting), st,
                        t.start, t.seed, s, &memory);
      lines += outcome_json(x).dump() + "\n";
      inserted += x.success, ++done;
      if (!o.quiet)
        std::cerr << "run: trial " << i << " " << name_of(st) << ": " << x.result << "\n";
      if (x.cell_fault) {  // the record says what happened; no further trial on this cell
        if (!o.out.empty()) write_file_atomic(o.out, lines);
        std::string why = x.result.substr(x.result.find(": ") + 2);  // after "refused: "
        if (why.rfind("cell " + o.endpoint + ": ", 0) == 0) why.erase(0, o.endpoint.size() + 7);
        throw Error("cell " + o.endpoint + ": trial " + std::to_string(i) + " stopped: " + why);
      }
    }
  if (!o.out.empty()) write_file_atomic(o.out, lines);
  std::cout << cs.task << " cell at " << o.endpoint << ": " << inserted << "/" << done
            << " inserted\n";
  return 0;
}

}  // namespace

Command add_run(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "run", "Run the on-line loop against a cell served over the cell protocol (gRPC)");
  app->add_option("--cell-endpoint", o->endpoint, "HOST:PORT of the cell (a bridge or cell-sim)")
      ->required();
  app->add_option("--cell", o->cell, "the cell's model (YAML, cells/*.yaml)")->required();
  app->add_option("--thresholds", o->thresholds, "tuned registration thresholds (laserfit tune)")
      ->required();
  app->add_option("--strategy", o->strategies, "comma-separated: ic1, ic2, laser, laser_pose")
      ->capture_default_str();
  app->add_option("--trials", o->trials, "trials per strategy")->capture_default_str();
  app->add_option("--first", o->first, "index of the first trial")->capture_default_str();
  app->add_option("--seed", o->seed, "the campaign's seed (as sim --seed)")->capture_default_str();
  app->add_option("--timeout", o->timeout_s,
                  "seconds a call may take beyond its motion or sweep (then: stop)")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  app->add_option("--tls-ca", o->tls_ca, "PEM of the CA that signed the cell's certificate: TLS");
  app->add_option("-o,--output,--out", o->out,
                  "every trial's outcome and decision log (JSON Lines)");
  add_verify_each_flag(*app, o->verify_each);
  add_forget_flag(*app, o->forget);
  app->add_flag("--quiet", o->quiet, "no progress on stderr");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::ctl
