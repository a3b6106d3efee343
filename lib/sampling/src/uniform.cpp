#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "sampling_internal.hpp"

namespace laserfit::sampling {

SurfaceSamples uniform_candidates(const TriMesh& mesh, size_t n, uint64_t seed,
                                  uint64_t first_block) {
  // Cumulative face areas in double: 100k faces of very different size stay exact enough.
  std::vector<double> cdf(mesh.faces.size());
  double total = 0.0;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    cdf[f] = total += mesh.face_area(static_cast<int>(f));
  if (!(total > 0.0)) throw Error("cannot sample a mesh of zero area");

  SurfaceSamples out;
  out.points.resize(n);
  out.normals.resize(n);
  const size_t blocks = (n + kBlock - 1) / kBlock;
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    auto rng = block_rng(seed, kStreamSurface, first_block + b);
    const size_t end = std::min(n, (b + 1) * kBlock);
    for (size_t i = b * kBlock; i < end; ++i) {
      const double u = uniform01(rng) * total;
      const size_t f = std::min<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin(),
                                        cdf.size() - 1);
      // Osada et al. 2002, eq. 1: P = (1 - sqrt r1) A + sqrt r1 (1 - r2) B + sqrt r1 r2 C.
      const double s1 = std::sqrt(uniform01(rng)), r2 = uniform01(rng);
      const auto& t = mesh.faces[f];
      const Eigen::Vector3d p = (1 - s1) * mesh.vertices[t[0]].cast<double>() +
                                s1 * (1 - r2) * mesh.vertices[t[1]].cast<double>() +
                                s1 * r2 * mesh.vertices[t[2]].cast<double>();
      out.points[i] = p.cast<float>();
      out.normals[i] = mesh.face_normal(static_cast<int>(f));
    }
  });
  return out;
}

PointCloud sample_uniform(const TriMesh& mesh, const SamplingSettings& s) {
  const size_t n = resolve_count(s, mesh.area());
  return to_cloud(uniform_candidates(mesh, n, s.seed), "uniform", s);
}

PointCloud sample_poisson_disk(const TriMesh& mesh, const SamplingSettings& s) {
  const double area = mesh.area();
  const size_t n = resolve_count(s, area);
  const size_t m = candidate_count(n, s.poisson_oversampling);
  return to_cloud(eliminate_to(uniform_candidates(mesh, m, s.seed), n, area), "poisson_disk", s);
}

}  // namespace laserfit::sampling
