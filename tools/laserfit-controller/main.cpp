// laserfit-controller: the on-line insertion controller.
//   sim      run the loop against the simulated dual-arm cell and report the outcomes
//   run      the loop against a cell over the cell protocol (gRPC): a lab's bridge or cell-sim
//   cell-sim serve the simulated cell over the cell protocol
//   correct  one correction from files (a scan, the references, the arm's pose), for use next to
//            real hardware: a trajectory CSV in the assembling arm's base frame
#include "commands.hpp"
#include "laserfit/core/build_info.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "laserfit-controller — scan, register, correct, insert (simulated cell or files). Lengths "
      "mm."};
  app.require_subcommand(1);
  app.set_version_flag("--version", laserfit::build_info());
  const std::vector<laserfit::ctl::Command> commands = {
      laserfit::ctl::add_sim(app), laserfit::ctl::add_correct(app), laserfit::ctl::add_run(app),
      laserfit::ctl::add_cell_sim(app)};
  return laserfit::tools::run_subcommand(app, commands, argc, argv, "laserfit-controller");
}
