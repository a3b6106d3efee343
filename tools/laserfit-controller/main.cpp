// laserfit-controller: the on-line insertion controller.
//   sim      run the loop against the simulated dual-arm cell and report the outcomes
//   correct  one correction from files (a scan, the references, the arm's pose), for use next to
//            real hardware: a trajectory CSV in the assembling arm's base frame
#include <CLI/CLI.hpp>
#include <iostream>

#include "commands.hpp"
#include "laserfit/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"laserfit-controller — scan, register, correct, insert (simulated cell or files). Lengths mm."};
  app.require_subcommand(1);
  auto sim = laserfit::ctl::add_sim(app);
  auto correct = laserfit::ctl::add_correct(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  for (auto* c : {&sim, &correct}) {
    if (!c->app->parsed()) continue;
    try {
      return c->run();
    } catch (const std::exception& e) {
      std::cerr << "laserfit-controller " << c->app->get_name() << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  return 1;
}
