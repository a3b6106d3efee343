#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace laserfit::ctl {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};
Command add_sim(CLI::App& root);
Command add_correct(CLI::App& root);

}  // namespace laserfit::ctl
