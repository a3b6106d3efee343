#include "laserfit/core/input_file.hpp"

#include <filesystem>
#include <system_error>

#include "laserfit/core/error.hpp"

namespace laserfit {

std::string shown_path(const std::string& path) {
  constexpr size_t kWhole = 160, kHead = 80, kTail = 60;
  if (path.size() <= kWhole) return path;
  return path.substr(0, kHead) + "[... " + std::to_string(path.size() - kHead - kTail) +
         " characters ...]" + path.substr(path.size() - kTail);
}

void require_input_file(const std::string& path, const std::string& role, EmptyFile empty) {
  namespace fs = std::filesystem;
  const std::string shown = shown_path(path);
  const std::string why = role.empty() ? "" : " (" + role + ")";
  if (path.empty()) throw Error("an input path is empty" + why);
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw Error(shown, "cannot use the path: " + ec.message() + why);
  if (!fs::exists(st)) throw Error(shown, (role.empty() ? "no such file" : "missing") + why);
  if (!fs::is_regular_file(st)) throw Error(shown, "not a regular file" + why);
  if (empty == EmptyFile::allowed) return;
  const auto size = fs::file_size(path, ec);
  if (ec) throw Error(shown, "cannot read the file: " + ec.message() + why);
  if (size == 0) throw Error(shown, "file is empty" + why);
}

bool is_existing_directory(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec) && !ec;
}

}  // namespace laserfit
