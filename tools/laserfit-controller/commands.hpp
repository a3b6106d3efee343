#pragma once
// The laserfit-controller subcommands.
#include "../common/subcommand.hpp"

namespace laserfit::ctl {

using tools::Command;
Command add_sim(CLI::App& root);
Command add_correct(CLI::App& root);
Command add_run(CLI::App& root);
Command add_cell_sim(CLI::App& root);

// --verify-each, shared by the commands that run the on-line loop (sim, run).
inline CLI::Option* add_verify_each_flag(CLI::App& app, bool& verify_each) {
  return app.add_flag("--verify-each", verify_each,
                      "verify every correction by a scan of its own (the paper's loop; default: a "
                      "correction goes with the move to the next waypoint, whose scan verifies "
                      "it, while that waypoint is outside the target or the correction is small: "
                      "2.5x the cell's clearance)");
}

// --forget, shared by sim and run: the arm's move error is learned per trial only.
inline CLI::Option* add_forget_flag(CLI::App& app, bool& forget) {
  return app.add_flag("--forget", forget,
                      "each trial starts knowing nothing of the arm's move error (default: it "
                      "starts from what the earlier trials on the same arm pair taught; the first "
                      "trial run knows nothing)");
}

}  // namespace laserfit::ctl
