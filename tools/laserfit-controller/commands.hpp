#pragma once
// The laserfit-controller subcommands.
#include "../common/subcommand.hpp"

namespace laserfit::ctl {

using tools::Command;
Command add_sim(CLI::App& root);
Command add_correct(CLI::App& root);
Command add_run(CLI::App& root);
Command add_cell_sim(CLI::App& root);

}  // namespace laserfit::ctl
