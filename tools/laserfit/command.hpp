#pragma once
// Each subcommand registers itself on the CLI11 app and returns the function that runs it.
#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <string>

#include "laserfit/io/json.hpp"

namespace laserfit::cli {

using Run = std::function<int()>;
struct Command {
  CLI::App* app;
  Run run;
};

Command add_import(CLI::App& root);
Command add_refcloud(CLI::App& root);
Command add_cad(CLI::App& root);
Command add_scan(CLI::App& root);
Command add_register(CLI::App& root);

// --json: the machine-readable result on stdout (and nothing else there); otherwise human text.
inline void emit(bool json, const io::Json& j, const std::string& human) {
  if (json)
    std::cout << j.dump(2) << "\n";
  else
    std::cout << human;
}

}  // namespace laserfit::cli
