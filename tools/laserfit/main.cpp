// laserfit: CAD import, reference clouds, scan synthesis, registration, benchmarks.
#include <exception>
#include <iostream>
#include <vector>

#include "command.hpp"
#include "laserfit/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"laserfit — um-precise robotic insertion: CAD -> reference clouds -> scans -> "
               "registration. All lengths in millimetres."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "laserfit 0.1.0");
  std::vector<laserfit::cli::Command> commands = {laserfit::cli::add_import(app),
                                                  laserfit::cli::add_refcloud(app),
                                                  laserfit::cli::add_cad(app),
                                                  laserfit::cli::add_scan(app),
                                                  laserfit::cli::add_register(app),
                                                  laserfit::cli::add_bench(app),
                                                  laserfit::cli::add_tune(app),
                                                  laserfit::cli::add_report(app, argc, argv)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  for (auto& c : commands) {
    if (!c.app->parsed()) continue;
    try {
      return c.run();
    } catch (const laserfit::Error& e) {
      std::cerr << "laserfit " << c.app->get_name() << ": error: " << e.what() << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "laserfit " << c.app->get_name() << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  return 1;
}
