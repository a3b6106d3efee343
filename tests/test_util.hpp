#pragma once
// Shared helpers for the tests: temporary directories and small meshes made by code.
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <tbb/global_control.h>

#include "laserfit/core/mesh.hpp"

namespace laserfit::test {

inline std::filesystem::path data(const std::string& rel) {
  return std::filesystem::path(LASERFIT_TEST_DATA) / rel;
}

// A fresh directory under the system temp dir, removed at scope exit.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / ("laserfit_test_" + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string operator/(const std::string& f) const { return (path / f).string(); }
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs f() with TBB limited to n threads (determinism tests compare 1 against 2 threads).
template <typename F>
auto with_threads(int n, F&& f) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, n);
  return f();
}

// Axis-aligned box [lo, hi] as 12 outward triangles sharing 8 vertices.
inline TriMesh box_mesh(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z());
  const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (auto& t : f) m.faces.emplace_back(t[0], t[1], t[2]);
  return m;
}

}  // namespace laserfit::test
