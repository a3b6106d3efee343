// laserfit report <results.jsonl...> -o reports/<name>/: Markdown tables and VTK-rendered PNGs.
#include <unistd.h>

#include <cstdlib>

#include "command.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/report/figures.hpp"
#include "laserfit/report/report.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::vector<std::string> results;
  std::string out, repetitions;
  bool json = false, no_overlays = false;
};

// Debian's VTK renders through X. Without a display, run this very command again under a
// private Xvfb server (xvfb-run, Debian package xvfb) instead of failing.
void ensure_display(int argc, char** argv) {
  if (report::have_display()) return;
  if (std::getenv("LASERFIT_UNDER_XVFB")) throw Error("no X display even under xvfb-run");
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0)
    throw Error(
        "no X display for VTK's off-screen rendering and no xvfb-run (apt-get install xvfb xauth)");
  setenv("LASERFIT_UNDER_XVFB", "1", 1);
  std::vector<char*> args = {const_cast<char*>("xvfb-run"), const_cast<char*>("-a"),
                             const_cast<char*>("-s"), const_cast<char*>("-screen 0 1600x1200x24")};
  for (int i = 0; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execvp("xvfb-run", args.data());
  throw Error("could not run xvfb-run");
}

int run(const Options& o) {
  report::ReportSettings s;
  s.results = o.results;
  s.out_dir = o.out;
  s.overlays = !o.no_overlays;
  if (!o.repetitions.empty()) s.only_repetitions = parse_range(o.repetitions, "--repetitions");
  const auto r = report::make_report(s);
  std::string h =
      "report of " + std::to_string(r.records) + " records -> " + o.out + "/README.md (";
  h += std::to_string(r.files.size()) + " files)\n";
  emit(o.json, {{"out", o.out}, {"records", r.records}, {"files", r.files}}, h);
  return 0;
}

}  // namespace

Command add_report(CLI::App& root, int argc, char** argv) {
  auto o = std::make_shared<Options>();
  auto* app =
      root.add_subcommand("report",
                          "Benchmark results -> Markdown tables and PNG figures (error CDFs, "
                          "success vs noise / outliers, time vs scan size, overlays)");
  app->add_option("results", o->results,
                  "results.jsonl files of laserfit bench (run.json and overlays/ next "
                  "to them are used)")
      ->required();
  app->add_option("-o,--output,--out", o->out, "report directory (README.md, PNGs, summary.csv)")
      ->required();
  app->add_flag("--no-overlays", o->no_overlays, "skip the overlay renderings");
  app->add_option(
      "--repetitions", o->repetitions,
      "only records of repetitions a:b (to compare runs of different lengths on the same scans)");
  app->add_flag("--json", o->json, "machine-readable summary on stdout");
  return {app, [o, argc, argv] {
            ensure_display(argc, argv);
            return run(*o);
          }};
}

}  // namespace laserfit::cli
