// View-dependent reference clouds: uniform candidates over the whole surface, kept when the
// scanner's own visibility rule (sensor/line_scanner) accepts them from at least one viewpoint.
#include <tbb/parallel_for.h>

#include <sstream>

#include "laserfit/core/error.hpp"
#include "laserfit/raycast/scene.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "sampling_internal.hpp"

namespace laserfit::sampling {
namespace {

// Visible subset of `c`, order preserved (deterministic whatever the threading).
SurfaceSamples keep_visible(const SurfaceSamples& c, const raycast::Scene& scene,
                            const std::vector<sensor::LineScannerView>& views) {
  std::vector<uint8_t> keep(c.points.size(), 0);
  tbb::parallel_for(size_t(0), c.points.size(), [&](size_t i) {
    for (const auto& view : views)
      if (view.visibility(scene, c.points[i], c.normals[i]) == sensor::Visibility::Visible) {
        keep[i] = 1;
        break;
      }
  });
  SurfaceSamples out;
  for (size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) out.points.push_back(c.points[i]), out.normals.push_back(c.normals[i]);
  return out;
}

}  // namespace

PointCloud sample_visible(const TriMesh& mesh, const ViewSettings& v, const SamplingSettings& s) {
  if (v.T_mesh_sensor.empty()) throw Error("view-dependent sampling needs at least one viewpoint");
  v.geometry.validate("viewpoint");
  raycast::Scene scene;
  scene.add_mesh(mesh);
  scene.commit();
  std::vector<sensor::LineScannerView> views;
  for (const auto& T : v.T_mesh_sensor) views.emplace_back(T, v.geometry, v.swept);
  const double area = mesh.area();
  const bool poisson = s.method == Method::PoissonDisk;
  const double over = poisson ? s.poisson_oversampling : 1.0;

  SurfaceSamples visible;
  size_t drawn = 0;
  double visible_fraction = 0.0;  // of the drawn candidates; estimates the visible area
  if (s.count > 0) {
    resolve_count(s, area);
    // Draw batches of candidates until enough are visible; the first N visible i.i.d. samples
    // are an unbiased uniform sample of the visible surface.
    const size_t want = poisson ? candidate_count(s.count, over) : s.count;
    const size_t batch_blocks = std::max<size_t>(16, (want + kBlock - 1) / kBlock);
    for (uint64_t first = 0; visible.points.size() < want; first += batch_blocks) {
      auto got = keep_visible(uniform_candidates(mesh, batch_blocks * kBlock, s.seed, first), scene,
                              views);
      drawn += batch_blocks * kBlock;
      visible.points.insert(visible.points.end(), got.points.begin(), got.points.end());
      visible.normals.insert(visible.normals.end(), got.normals.begin(), got.normals.end());
      if (drawn >= kMaxPoints || (drawn >= 4 * want && visible.points.empty())) break;
    }
    if (visible.points.size() < want) {
      std::ostringstream m;
      m << "only " << visible.points.size() << " of " << drawn
        << " surface samples are visible from the viewpoint(s); check the view poses (the part "
           "must lie "
        << v.geometry.z_min_mm << ".." << v.geometry.z_max_mm << " mm in front of the sensor)";
      throw Error(m.str());
    }
    visible_fraction = double(visible.points.size()) / double(drawn);
    visible.points.resize(want), visible.normals.resize(want);
  } else {
    drawn = static_cast<size_t>(std::ceil(resolve_count(s, area) * over));
    visible = keep_visible(uniform_candidates(mesh, drawn, s.seed), scene, views);
    if (visible.points.empty())
      throw Error("no surface point is visible from the viewpoint(s); check the view poses");
    visible_fraction = double(visible.points.size()) / double(drawn);
  }
  const double visible_area = area * visible_fraction;
  if (poisson) {
    const size_t target =
        s.count > 0 ? s.count : std::max<size_t>(1, size_t(visible.points.size() / over));
    visible = eliminate_to(visible, target, visible_area);
  }
  PointCloud c = to_cloud(std::move(visible), poisson ? "poisson_disk" : "uniform", s);
  std::ostringstream va;
  va << visible_area;
  c.metadata["visible_area_mm2"] = va.str();
  return c;
}

}  // namespace laserfit::sampling
