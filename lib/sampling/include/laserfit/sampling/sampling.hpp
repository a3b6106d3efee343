#pragma once
// Reference clouds from CAD meshes: full-surface (uniform, Poisson-disk) and view-dependent
// (only what a scanner at given viewpoints measures). Seeded; the output is bit-identical for a
// seed whatever the number of threads.
#include <cstdint>
#include <vector>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/mesh.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/sensor/line_scanner.hpp"

namespace laserfit::sampling {

enum class Method { Uniform, PoissonDisk };

struct SamplingSettings {
  Method method = Method::Uniform;
  size_t count = 0;              // number of points; or
  double density_per_mm2 = 0.0;  // points per mm^2 of (visible) surface
  uint64_t seed = 1;
  double poisson_oversampling = 5.0;  // candidates per output point for sample elimination
};

// Area-weighted i.i.d. samples (Osada et al. 2002, eq. 1) with the face normal of each sample.
PointCloud sample_uniform(const TriMesh& mesh, const SamplingSettings& s);

// Poisson-disk distribution by weighted sample elimination (Yuksel 2015) from uniform candidates.
PointCloud sample_poisson_disk(const TriMesh& mesh, const SamplingSettings& s);

struct ViewSettings {
  std::vector<Pose> T_mesh_sensor;  // viewpoints: sensor poses in the mesh frame
  sensor::LineScannerGeometry geometry;
  bool swept = true;  // line scanner swept along its y axis (see line_scanner.hpp)
};

// Surface points visible from at least one viewpoint (union of views), by the scanner's own
// visibility rule, sampled as `s` asks over the visible part of the surface only.
PointCloud sample_visible(const TriMesh& mesh, const ViewSettings& views,
                          const SamplingSettings& s);

// Building block shared by the above: `n` uniform surface samples of blocks [first, first+n/B)
// in a fixed order, independent of threading.
struct SurfaceSamples {
  std::vector<Eigen::Vector3f> points, normals;
};
SurfaceSamples uniform_candidates(const TriMesh& mesh, size_t n, uint64_t seed,
                                  uint64_t first_block = 0);

// Poisson-disk elimination of `in` down to `target` points (Yuksel 2015), area = surface area.
SurfaceSamples eliminate_to(const SurfaceSamples& in, size_t target, double area_mm2);

}  // namespace laserfit::sampling
