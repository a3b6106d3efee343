#pragma once
// What every fuzz target shares: the bytes go into a file (laserfit's readers take paths, as the
// CLI does), and a laserfit::Error is the expected answer to bad input — anything else (a crash,
// a sanitizer report, another exception type, a hang) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace laserfit::fuzz {

// A private folder for this process's input files, removed at exit.
inline const std::filesystem::path& work_dir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      const char* tmp = std::getenv("TMPDIR");
      path = std::filesystem::path(tmp ? tmp : "/tmp") /
             ("laserfit-fuzz-" + std::to_string(::getpid()));
      std::filesystem::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static Dir dir;
  return dir.path;
}

// Writes the input to work_dir()/name and returns the path.
inline std::string input_file(const std::string& name, const uint8_t* data, size_t size) {
  const std::filesystem::path p = work_dir() / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p.string();
}

// A copy of the repository's layout around the configuration files, so that a scene's meshes
// (../../cad/...), a benchmark's scenes (../datasets/scenes/...) and a cell's scene resolve as
// they do in the repository: cad/ and tests/ link to the sources, datasets/scenes holds copies,
// datasets/recorded a recorded scene's scene_gt.json.
// Returns work_dir(); inputs go to datasets/scenes/, benchmarks/ or cells/ under it.
inline const std::filesystem::path& repository_fixture() {
  namespace fs = std::filesystem;
  static const bool made = [] {
    const fs::path src = LASERFIT_SOURCE_DIR, w = work_dir();
    for (const char* d : {"cad", "tests"}) fs::create_directory_symlink(src / d, w / d);
    for (const char* d : {"datasets/scenes", "benchmarks", "cells"}) fs::create_directories(w / d);
    for (const auto& e : fs::directory_iterator(src / "datasets/scenes"))
      fs::copy_file(e.path(), w / "datasets/scenes" / e.path().filename());
    fs::create_directories(w / "datasets/recorded");  // a recorded scene's ground truth
    std::ofstream(w / "datasets/recorded/scene_gt.json")
        << R"({"0": [{"obj_id": 1, "cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0,0,9]}]})";
    return true;
  }();
  (void)made;
  return work_dir();
}

}  // namespace laserfit::fuzz
