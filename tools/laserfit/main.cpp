// laserfit: CAD import, reference clouds, scan synthesis, registration, benchmarks.
#include <vector>

#include "command.hpp"
#include "laserfit/core/build_info.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "laserfit — um-precise robotic insertion: CAD -> reference clouds -> scans -> "
      "registration. All lengths in millimetres."};
  app.require_subcommand(1);
  app.set_version_flag("--version", laserfit::build_info());
  std::vector<laserfit::cli::Command> commands = {laserfit::cli::add_import(app),
                                                  laserfit::cli::add_refcloud(app),
                                                  laserfit::cli::add_cad(app),
                                                  laserfit::cli::add_scan(app),
                                                  laserfit::cli::add_assemble(app),
                                                  laserfit::cli::add_register(app),
                                                  laserfit::cli::add_bench(app),
                                                  laserfit::cli::add_tune(app),
                                                  laserfit::cli::add_report(app, argc, argv)};
  return laserfit::tools::run_subcommand(app, commands, argc, argv, "laserfit");
}
