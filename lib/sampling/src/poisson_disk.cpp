// Weighted sample elimination: C. Yuksel, "Sample Elimination for Generating Poisson Disk Sample
// Sets", Computer Graphics Forum 34(2), 2015. Removes the most crowded candidate until `target`
// remain; deterministic (ties broken by index), so the output depends only on the seed.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "laserfit/sampling/sampling.hpp"
#include "sampling_internal.hpp"

namespace laserfit::sampling {
namespace {

// Uniform grid over the candidates with cells of the neighbourhood diameter 2 r_max.
class Grid {
 public:
  Grid(const std::vector<Eigen::Vector3f>& pts, float cell) : cell_(cell) {
    for (size_t i = 0; i < pts.size(); ++i) cells_[key(pts[i])].push_back(static_cast<int>(i));
  }
  template <typename F>
  void for_neighbours(const Eigen::Vector3f& p, F&& f) const {
    const Eigen::Vector3i c = coord(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(pack(c + Eigen::Vector3i(dx, dy, dz)));
          if (it != cells_.end())
            for (int j : it->second) f(j);
        }
  }

 private:
  Eigen::Vector3i coord(const Eigen::Vector3f& p) const {
    return (p / cell_).array().floor().cast<int>();
  }
  static uint64_t pack(const Eigen::Vector3i& c) {
    return (uint64_t(uint32_t(c.x()) & 0x1FFFFF) << 42) |
           (uint64_t(uint32_t(c.y()) & 0x1FFFFF) << 21) | uint64_t(uint32_t(c.z()) & 0x1FFFFF);
  }
  uint64_t key(const Eigen::Vector3f& p) const { return pack(coord(p)); }
  float cell_;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

// Binary max-heap over weights with positions, so a neighbour's weight can be lowered in place.
class WeightHeap {
 public:
  explicit WeightHeap(std::vector<double>& w) : w_(w), pos_(w.size()) {
    heap_.resize(w.size());
    for (size_t i = 0; i < w.size(); ++i)
      heap_[i] = static_cast<int>(i), pos_[i] = static_cast<int>(i);
    for (int i = static_cast<int>(heap_.size()) / 2 - 1; i >= 0; --i) down(i);
  }
  int pop() {
    const int top = heap_[0];
    swap_at(0, static_cast<int>(heap_.size()) - 1);
    heap_.pop_back();
    pos_[top] = -1;
    if (!heap_.empty()) down(0);
    return top;
  }
  void decreased(int i) {
    if (pos_[i] >= 0) down(pos_[i]);
  }
  bool alive(int i) const { return pos_[i] >= 0; }
  size_t size() const { return heap_.size(); }

 private:
  bool above(int a, int b) const { return w_[a] > w_[b] || (w_[a] == w_[b] && a < b); }
  void swap_at(int a, int b) {
    std::swap(heap_[a], heap_[b]);
    pos_[heap_[a]] = a, pos_[heap_[b]] = b;
  }
  void down(int i) {
    const int n = static_cast<int>(heap_.size());
    for (;;) {
      int best = i;
      for (int c : {2 * i + 1, 2 * i + 2})
        if (c < n && above(heap_[c], heap_[best])) best = c;
      if (best == i) return;
      swap_at(i, best);
      i = best;
    }
  }
  std::vector<double>& w_;
  std::vector<int> heap_, pos_;
};

}  // namespace

SurfaceSamples eliminate_to(const SurfaceSamples& in, size_t target, double area) {
  const size_t m = in.points.size();
  if (target >= m) return in;
  // Yuksel eq. 5 (2-D sampling domain) and eq. 6-7: r_max, r_min and the weight function.
  const double r_max = std::sqrt(area / (2.0 * std::sqrt(3.0) * double(target)));
  const double r_min = r_max * (1.0 - std::pow(double(target) / double(m), 1.5)) * 0.65;
  const double d_max = 2 * r_max;
  constexpr double alpha = 8.0;
  // (1 - d/d_max)^8 by three squarings: std::pow dominated the run time.
  auto weight = [&](int i, int j) {
    const double d = (in.points[i] - in.points[j]).cast<double>().norm();
    if (i == j || d >= d_max) return 0.0;
    double x = 1.0 - std::max(d, 2 * r_min) / d_max;
    x *= x, x *= x, x *= x;
    static_assert(alpha == 8.0, "the squarings above implement alpha = 8");
    return x;
  };
  // Neighbour lists with their weights, built once in parallel (each list in a fixed order).
  const Grid grid(in.points, static_cast<float>(d_max));
  std::vector<std::vector<std::pair<int, float>>> nbrs(m);
  std::vector<double> w(m, 0.0);
  tbb::parallel_for(size_t(0), m, [&](size_t i) {
    grid.for_neighbours(in.points[i], [&](int j) {
      const double wij = weight(int(i), j);
      if (wij > 0) nbrs[i].emplace_back(j, float(wij)), w[i] += float(wij);  // as subtracted later
    });
  });
  WeightHeap heap(w);
  while (heap.size() > target) {
    const int i = heap.pop();
    for (const auto& [j, wij] : nbrs[i])
      if (heap.alive(j)) {
        w[j] -= wij;
        heap.decreased(j);
      }
  }
  SurfaceSamples out;
  for (size_t i = 0; i < m; ++i)
    if (heap.alive(int(i))) {
      out.points.push_back(in.points[i]);
      out.normals.push_back(in.normals[i]);
    }
  return out;
}

}  // namespace laserfit::sampling
