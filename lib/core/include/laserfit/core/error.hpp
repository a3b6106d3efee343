#pragma once
// One error type for every stage: what went wrong and with which file, so that a CLI can print
// exactly one line ("<file>: <problem>") and exit non-zero.
#include <stdexcept>
#include <string>

namespace laserfit {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
  Error(const std::string& file, const std::string& what)
      : std::runtime_error(file.empty() ? what : file + ": " + what) {}
};

}  // namespace laserfit
