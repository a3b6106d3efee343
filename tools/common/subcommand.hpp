#pragma once
// What both CLIs share: each subcommand registers itself on the CLI11 app and returns the function
// that runs it; main parses, runs the chosen one and turns an exception into one line on stderr.
#include <tbb/global_control.h>
#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "laserfit/core/cpu_budget.hpp"

namespace laserfit::tools {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};

// The exit codes of both programs, shown at the end of every --help.
enum ExitCode : int { kDone = 0, kBadInput = 1, kUsage = 2, kNotTrusted = 3 };
inline constexpr const char* kExitCodes =
    "Exit codes: 0 done; 1 bad input or refused (one line on stderr naming the file or peer and "
    "the problem; no output file); 2 usage error (unknown option, value out of range); 3 done, "
    "but a registration has the status named by --fail-on.";

// A length-unit option (default mm) for inputs that do not state their unit; results stay in mm.
inline CLI::Option* add_unit_option(CLI::App& app, const std::string& name, std::string& unit,
                                    const std::string& what) {
  return app.add_option(name, unit, what + ": mm | m | um | cm | in")
      ->check(CLI::IsMember({"mm", "m", "um", "cm", "in"}))
      ->capture_default_str();
}

// "<program> <subcommand>: error: <what>" and exit code 1 on any error; a usage error is one line
// and exit code 2; --help and --version exit 0.
inline int run_subcommand(CLI::App& app, const std::vector<Command>& commands, int argc,
                          char** argv, const std::string& program) {
  const std::function<void(CLI::App*)> footer = [&](CLI::App* a) {
    a->footer(kExitCodes);
    for (CLI::App* sub : a->get_subcommands({})) footer(sub);
  };
  footer(&app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, as for any other bad input; usage errors exit 2.
    std::cerr << program << ": error: " << e.what() << " (see --help)\n";
    return kUsage;
  }
  for (const auto& c : commands) {
    if (!c.app->parsed()) continue;
    // --jobs, where a command has it, bounds every pool: TBB's, PCL's OpenMP and laserfit's own;
    // without it TBB gets what the process may use (a cgroup quota or Slurm's CPUs, not the cores).
    std::optional<tbb::global_control> tbb_limit;
    if (const CLI::Option* jobs = c.app->get_option_no_throw("--jobs")) {
      const int n = jobs->count() > 0 ? jobs->as<int>() : 0;
      if (n > 0) set_thread_limit(n);
      tbb_limit.emplace(tbb::global_control::max_allowed_parallelism,
                        size_t(n > 0 ? n : cpu_budget().jobs));
    }
    try {
      return c.run();
    } catch (const std::exception& e) {
      std::cerr << program << " " << c.app->get_name() << ": error: " << e.what() << "\n";
      return kBadInput;
    }
  }
  return 1;
}

}  // namespace laserfit::tools
