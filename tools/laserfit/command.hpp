#pragma once
// The laserfit subcommands (each registers itself and returns the function that runs it).
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "laserfit/core/error.hpp"

#include "../common/subcommand.hpp"
#include "laserfit/io/json.hpp"

namespace laserfit::cli {

using tools::Command;

Command add_import(CLI::App& root);
Command add_refcloud(CLI::App& root);
Command add_cad(CLI::App& root);
Command add_scan(CLI::App& root);
Command add_assemble(CLI::App& root);
Command add_register(CLI::App& root);
Command add_bench(CLI::App& root);
Command add_tune(CLI::App& root);
Command add_report(CLI::App& root, int argc, char** argv);  // re-executes under xvfb-run without X

// --json: the machine-readable result on stdout (and nothing else there); otherwise human text.
inline void emit(bool json, const io::Json& j, const std::string& human) {
  if (json)
    std::cout << j.dump(2) << "\n";
  else
    std::cout << human;
}

// --timeout and --reader-memory: the limits of the child process a CAD/mesh parser runs in.
inline void add_reader_limits(CLI::App& app, double& timeout_s, double& memory_mib) {
  app.add_option("--timeout", timeout_s,
                 "seconds the CAD/mesh parser may take before the file is refused (0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option(
         "--reader-memory", memory_mib,
         "MiB of memory the CAD/mesh parser may use before the file is refused (0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

// --jobs on a command that works in parallel: the threads it may use, in every pool (TBB, PCL's
// OpenMP, laserfit's own; run_subcommand applies it). The results do not depend on it.
inline void add_jobs(CLI::App& app, int& jobs) {
  app.add_option("--jobs", jobs, "threads at most (default: all this process may use)")
      ->check(CLI::PositiveNumber);
}

// "a, b, c" (for --help texts listing an enum's names).
inline std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// "a:b" -> a, a+1, ..., b-1 (repetitions of a benchmark's cells, as tuning splits them).
inline std::vector<int> parse_range(const std::string& text, const std::string& what) {
  int a = 0, b = 0;
  char c = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> a >> c >> b) || c != ':' || a < 0 || b <= a || (in >> extra))
    throw Error(what + " '" + text + "': expected a:b with 0 <= a < b");
  std::vector<int> v;
  for (int i = a; i < b; ++i) v.push_back(i);
  return v;
}

}  // namespace laserfit::cli
