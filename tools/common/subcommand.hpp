#pragma once
// What both CLIs share: each subcommand registers itself on the CLI11 app and returns the function
// that runs it; main parses, runs the chosen one and turns an exception into one line on stderr.
#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace laserfit::tools {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};

// "<program> <subcommand>: error: <what>" and exit code 1 on any error; a usage error is one line
// and exit code 2; --help and --version exit 0.
inline int run_subcommand(CLI::App& app, const std::vector<Command>& commands, int argc,
                          char** argv, const std::string& program) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, as for any other bad input; usage errors exit 2.
    std::cerr << program << ": error: " << e.what() << " (see --help)\n";
    return 2;
  }
  for (const auto& c : commands) {
    if (!c.app->parsed()) continue;
    try {
      return c.run();
    } catch (const std::exception& e) {
      std::cerr << program << " " << c.app->get_name() << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  return 1;
}

}  // namespace laserfit::tools
