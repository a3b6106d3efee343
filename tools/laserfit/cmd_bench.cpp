// laserfit bench <benchmark.yaml> [--methods a,b] [--shard i/N] [--out DIR] [--jobs J] ...
// laserfit bench generate <benchmark.yaml> [-o datasets/<name>]   (scans + ground truth + manifest)
// laserfit bench merge DIR... -o OUT                                (shards -> one run)
// laserfit bench export <benchmark.yaml> --bop -o DIR                (recorded scenes, BOP layout)
#include <map>
#include <thread>

#include "command.hpp"
#include "laserfit/bench/dataset.hpp"
#include "laserfit/bench/recorded.hpp"
#include "laserfit/bench/runner.hpp"
#include "laserfit/core/cpu_budget.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string file, methods, shard = "0/1", out, dataset, thresholds, repetitions, scenes;
  int jobs = 0;
  bool json = false, no_overlays = false, quiet = false, list = false;
  std::string gen_file, gen_out;
  bool verify = false;
  std::vector<std::string> merge_dirs;
  std::string merge_out;
  bool bop = false;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> v;
  std::string x;
  for (std::stringstream in(s); std::getline(in, x, ',');)
    if (!x.empty()) v.push_back(x);
  return v;
}

// --jobs, or what this process was given (CPU affinity, cgroup quota, SLURM_CPUS_PER_TASK).
CpuBudget jobs_or_default(int jobs) { return jobs > 0 ? CpuBudget{jobs, "--jobs"} : cpu_budget(); }

// --list: check the file and say what a run would do.
int run_list(const Options& o, const bench::Benchmark& b) {
  const auto trials = bench::enumerate_trials(b);
  const auto shard = bench::parse_shard(o.shard);
  std::map<std::string, int> per_scene;
  int mine = 0;
  for (const auto& t : bench::select_trials(b, {}, split(o.scenes)))
    if (shard.contains(t)) ++mine, ++per_scene[b.scenes[t.scene].name];
  io::Json j = {{"benchmark", b.name},     {"seed", b.seed},
                {"mode", name_of(b.mode)}, {"trials_total", trials.size()},
                {"shard", shard.text()},   {"trials", mine},
                {"per_scene", per_scene},  {"methods", io::Json::array()}};
  for (const auto m : b.methods) j["methods"].push_back(name_of(m));
  std::ostringstream h;
  h << b.name << " (seed " << b.seed << ", " << name_of(b.mode) << "): " << trials.size()
    << " trials in all, " << mine << " in shard " << shard.text() << " (";
  for (const auto& [n, c] : per_scene)
    h << n << " " << c << (n == per_scene.rbegin()->first ? "" : ", ");
  h << "); methods";
  for (const auto m : b.methods) h << " " << name_of(m);
  h << "\n";
  emit(o.json, j, h.str());
  return 0;
}

int run_export(const Options& o) {
  const auto b = bench::load_benchmark(o.gen_file);
  const auto s = bench::export_bop(
      b, o.gen_out, jobs_or_default(o.jobs).jobs,
      o.repetitions.empty() ? std::vector<int>{} : parse_range(o.repetitions, "--repetitions"),
      split(o.scenes));
  emit(o.json,
       {{"out", o.gen_out}, {"trials", s.trials}, {"objects", s.objects}, {"wall_s", s.wall_s}},
       "wrote " + std::to_string(s.trials) + " scans of " + std::to_string(s.objects) +
           " objects as recorded scenes (BOP layout) to " + o.gen_out +
           "; run them with: " + "laserfit bench " + o.gen_out + "/benchmark.yaml\n");
  return 0;
}

int run(const Options& o, CLI::App* gen, CLI::App* merge, CLI::App* exp) {
  if (exp->parsed()) return run_export(o);
  if (merge->parsed()) {
    const auto s = bench::merge_runs(o.merge_dirs, o.merge_out);
    emit(o.json, {{"out", o.merge_out}, {"trials", s.trials}, {"records", s.records}},
         "merged " + std::to_string(o.merge_dirs.size()) + " shards: " + std::to_string(s.trials) +
             " trials, " + std::to_string(s.records) + " records -> " + o.merge_out +
             "/results.jsonl\n");
    return 0;
  }
  if (gen->parsed()) {
    const auto b = bench::load_benchmark(o.gen_file);
    const std::string dir = o.gen_out.empty() ? "datasets/" + b.name : o.gen_out;
    if (o.verify) {
      bench::verify_dataset(dir);
      emit(o.json, {{"dataset", dir}, {"verified", true}},
           dir + ": every file matches its manifest\n");
      return 0;
    }
    const auto s = bench::generate_dataset(
        b, dir, jobs_or_default(o.jobs).jobs,
        o.repetitions.empty() ? std::vector<int>{} : parse_range(o.repetitions, "--repetitions"),
        split(o.scenes));
    emit(o.json,
         {{"dataset", dir},
          {"trials", s.trials},
          {"bytes", s.bytes},
          {"wall_s", s.wall_s},
          {"seed", b.seed}},
         "wrote " + std::to_string(s.trials) + " trials (" + std::to_string(s.bytes >> 20) +
             " MiB) to " + dir + " (seed " + std::to_string(b.seed) + ")\n");
    return 0;
  }
  if (o.file.empty())
    throw Error("give a benchmark file (or the generate / merge subcommand); see --help");
  const auto b = bench::load_benchmark(o.file);
  if (o.list) return run_list(o, b);
  bench::RunSettings s;
  for (const auto& m : split(o.methods)) s.methods.push_back(parse_enum<registration::Method>(m));
  s.shard = bench::parse_shard(o.shard);
  s.out_dir = o.out.empty() ? "out/bench/" + b.name : o.out;
  s.dataset_dir = o.dataset;
  s.thresholds_file = o.thresholds;
  const CpuBudget budget = jobs_or_default(o.jobs);
  s.jobs = budget.jobs, s.jobs_source = budget.source;
  if (!o.repetitions.empty()) s.only_repetitions = parse_range(o.repetitions, "--repetitions");
  s.only_scenes = split(o.scenes);
  s.overlays = !o.no_overlays;
  s.progress = !o.quiet;
  const auto r = bench::run_benchmark(b, s);
  std::ostringstream h;
  h.precision(3);
  h << b.name << " (seed " << b.seed << ", shard " << s.shard.text() << "): " << r.trials
    << " trials (" << r.resumed << " resumed), " << r.records << " records in " << r.wall_s
    << " s, " << r.trials_per_s << " trials/s -> " << s.out_dir << "/results.jsonl, summary.csv\n";
  emit(o.json,
       {{"benchmark", b.name},
        {"seed", b.seed},
        {"shard", s.shard.text()},
        {"out", s.out_dir},
        {"trials", r.trials},
        {"resumed", r.resumed},
        {"records", r.records},
        {"wall_s", r.wall_s},
        {"trials_per_s", r.trials_per_s}},
       h.str());
  return 0;
}

}  // namespace

Command add_bench(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "bench",
      "Run a benchmark (benchmarks/*.yaml): every trial x target x method in parallel, resumable, "
      "shardable; results.jsonl + summary.csv + run.json in --out.");
  app->add_option("benchmark", o->file, "benchmark definition (YAML)");
  app->add_option("--methods", o->methods,
                  "comma-separated methods (default: the benchmark's): " +
                      join(names_of<registration::Method>()));
  app->add_option("--shard", o->shard,
                  "run one deterministic slice i/N (trials k with k mod N = i)")
      ->capture_default_str();
  app->add_option("-o,--output,--out", o->out,
                  "result directory (default out/bench/<name>); an interrupted run there resumes");
  app->add_option("--jobs", o->jobs,
                  "trials in parallel (default: the CPUs this process may use: affinity, cgroup "
                  "quota, SLURM_CPUS_PER_TASK; 1 gives per-trial peak memory)");
  app->add_option("--dataset", o->dataset,
                  "read scans from a generated dataset instead of simulating them");
  app->add_option("--thresholds", o->thresholds,
                  "tuned thresholds (laserfit tune) on top of each method");
  app->add_option("--repetitions", o->repetitions,
                  "only repetitions a:b of every cell (as tuning splits)");
  app->add_option("--scenes", o->scenes,
                  "comma-separated: only these scenes (same trials and seeds as in a full run)");
  app->add_flag("--no-overlays", o->no_overlays,
                "do not write overlay clouds of each scene's first trial");
  app->add_flag("--quiet", o->quiet, "no progress on stderr");
  app->add_flag("--list", o->list,
                "check the benchmark file and print its trials per scene; run nothing");
  app->add_flag("--json", o->json, "machine-readable summary on stdout");
  auto* gen = app->add_subcommand(
      "generate", "Write the benchmark's dataset: scans, ground truth, manifest with CRC-32s");
  gen->add_option("benchmark", o->gen_file, "benchmark definition (YAML)")->required();
  gen->add_option("-o,--output,--out", o->gen_out, "dataset directory (default datasets/<name>)");
  gen->add_option("--jobs", o->jobs, "trials in parallel (the bytes do not depend on it)");
  gen->add_option("--repetitions", o->repetitions, "only repetitions a:b of every cell");
  gen->add_option("--scenes", o->scenes, "comma-separated: only these scenes");
  gen->add_flag("--verify", o->verify, "only check an existing dataset against its manifest");
  gen->add_flag("--json", o->json, "machine-readable summary on stdout");
  auto* merge =
      app->add_subcommand("merge", "Combine the result directories of shards 0..N-1 into one run");
  merge->add_option("dirs", o->merge_dirs, "shard result directories")->required();
  merge->add_option("-o,--output,--out", o->merge_out, "merged result directory")->required();
  merge->add_flag("--json", o->json, "machine-readable summary on stdout");
  auto* exp = app->add_subcommand(
      "export",
      "Write the benchmark's simulated scans as recorded scenes in BOP's layout (scene_gt.json, "
      "models/, scans/) with a benchmark.yaml that runs them: the form of a lab's own dataset");
  exp->add_option("benchmark", o->gen_file, "benchmark definition (YAML)")->required();
  exp->add_flag("--bop", o->bop,
                "BOP layout (the one there is; required, so that a script "
                "that says it keeps working when there are others)")
      ->required();
  exp->add_option("-o,--output", o->gen_out, "dataset directory")->required();
  exp->add_option("--jobs", o->jobs, "trials in parallel (the bytes do not depend on it)");
  exp->add_option("--repetitions", o->repetitions, "only repetitions a:b of every cell");
  exp->add_option("--scenes", o->scenes, "comma-separated: only these scenes");
  exp->add_flag("--json", o->json, "machine-readable summary on stdout");
  return {app, [o, gen, merge, exp] { return run(*o, gen, merge, exp); }};
}

}  // namespace laserfit::cli
