// laserfit tune <benchmark.yaml> --train a:b --test c:d -o thresholds.yaml: search the registration
// parameters on the training repetitions, measure the winner on the held-out ones, write the
// thresholds file the controller reads.
#include <thread>

#include "command.hpp"
#include "laserfit/bench/tune.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/cpu_budget.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string file, train, test, out, method = "ceres", params, log;
  int jobs = 0;
  bool json = false, quiet = false;
};

int run(const Options& o) {
  const auto b = bench::load_benchmark(o.file);
  bench::TuneSettings s;
  s.method = parse_enum<registration::Method>(o.method);
  const int half = std::max(1, b.trials / 2);
  s.train = parse_range(o.train.empty() ? "0:" + std::to_string(half) : o.train, "--train");
  s.test = parse_range(
      o.test.empty() ? std::to_string(half) + ":" + std::to_string(b.trials) : o.test, "--test");
  std::string p;
  for (std::stringstream in(o.params); std::getline(in, p, ',');)
    if (!p.empty()) s.params.push_back(p);
  s.jobs = o.jobs > 0 ? o.jobs : cpu_budget().jobs;
  s.progress = !o.quiet;
  const auto r = bench::tune(b, s);
  registration::write_thresholds(o.out, r.thresholds);
  const io::Json j = {{"thresholds", o.out},
                      {"benchmark", b.name},
                      {"seed", b.seed},
                      {"method", name_of(s.method)},
                      {"train", r.thresholds.train},
                      {"test", r.thresholds.test},
                      {"train_success_defaults", r.baseline_train.success_rate()},
                      {"train_success_tuned", r.best_train.success_rate()},
                      {"held_out_success_defaults", r.baseline_held_out.success_rate()},
                      {"held_out_success_tuned", r.held_out.success_rate()},
                      {"held_out_false_accepts_tuned", r.held_out.false_accepts},
                      {"held_out_false_accepts_defaults", r.baseline_held_out.false_accepts},
                      {"history", r.history}};
  if (!o.log.empty()) write_file_atomic(o.log, j.dump(2) + "\n");
  std::ostringstream h;
  h.precision(3);
  h << "tuned on repetitions " << r.thresholds.train << " of " << b.name << ", held out "
    << r.thresholds.test << ": success " << 100 * r.held_out.success_rate() << " % (defaults "
    << 100 * r.baseline_held_out.success_rate() << " %), false accepts " << r.held_out.false_accepts
    << " (defaults " << r.baseline_held_out.false_accepts << ") -> " << o.out << "\n";
  emit(o.json, j, h.str());
  return 0;
}

}  // namespace

Command add_tune(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app =
      root.add_subcommand("tune",
                          "Tune the registration thresholds on a benchmark's training repetitions, "
                          "measure them on held-out ones, write thresholds.yaml");
  app->add_option("benchmark", o->file, "benchmark definition (YAML)")->required();
  app->add_option("--train", o->train,
                  "training repetitions a:b of every cell (default: the first half)");
  app->add_option("--test", o->test, "held-out repetitions c:d (default: the second half)");
  app->add_option("-o,--output,--out", o->out, "thresholds file to write (YAML)")->required();
  app->add_option("--method", o->method, "method to tune")
      ->check(CLI::IsMember(names_of<registration::Method>()))
      ->capture_default_str();
  app->add_option("--params", o->params,
                  "comma-separated parameters to search (default all): rho_rot, rho_icp, "
                  "max_rmse, min_overlap, voxel_scale, feature_radius, ransac_iterations, "
                  "max_correspondence");
  app->add_option("--jobs", o->jobs, "trials in parallel (default: all cores)");
  app->add_option("--log", o->log, "write every evaluation of the search here (JSON)");
  app->add_flag("--quiet", o->quiet, "no progress on stderr");
  app->add_flag("--json", o->json, "machine-readable summary on stdout");
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
