#pragma once
// Benchmark inputs shared by the benchmark executables.
#include <algorithm>
#include <map>
#include <string>

#include "laserfit/cad/import.hpp"

namespace laserfit::bench {

inline std::string data(const char* f) { return std::string(LASERFIT_TEST_DATA) + "/o2ac/" + f; }

// Splits triangle f 1 -> 4 at its edge midpoints (midpoints shared through `mid`, so neighbours
// that are split too stay connected).
inline void split4(TriMesh& m, int f, std::map<std::pair<int, int>, int>& mid) {
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    m.vertices.push_back((m.vertices[a] + m.vertices[b]) / 2);
    return mid[key] = int(m.vertices.size()) - 1;
  };
  const Eigen::Vector3i t = m.faces[f];
  const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
  m.faces[f] = {ab, bc, ca};
  m.faces.push_back({t[0], ab, ca});
  m.faces.push_back({ab, t[1], bc});
  m.faces.push_back({ca, bc, t[2]});
}

// The real gear-motor mesh (9 872 triangles) refined to 100 000 triangles by midpoint
// subdivision (every face once, then the largest ones again), which keeps the triangles' shapes
// and the real CAD area distribution.
inline const TriMesh& mesh_100k() {
  static const TriMesh m = [] {
    TriMesh mesh = cad::import_cad(data("04_37D-GEARMOTOR-50-70.obj")).mesh;
    std::map<std::pair<int, int>, int> mid;
    for (int f = 0, n = int(mesh.faces.size()); f < n; ++f) split4(mesh, f, mid);
    std::vector<std::pair<double, int>> by_area;
    for (int f = 0; f < int(mesh.faces.size()); ++f) by_area.push_back({-mesh.face_area(f), f});
    std::sort(by_area.begin(), by_area.end());
    const size_t extra = (100000 - mesh.faces.size()) / 3;  // each split adds 3 faces
    for (size_t k = 0; k < extra; ++k) split4(mesh, by_area[k].second, mid);
    return mesh;
  }();
  return m;
}

}  // namespace laserfit::bench
