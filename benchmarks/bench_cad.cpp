// CAD import and reference-cloud sampling speed (issue: <= 0.2 s for 1 M uniform points from a
// 100 k-triangle mesh on 2 cores). Run: make bench-cad -> reports/cad/.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "bench_meshes.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/sampling/sampling.hpp"

using namespace laserfit;
using laserfit::bench::data;
using laserfit::bench::mesh_100k;

namespace {

void BM_Import(benchmark::State& st, const char* file) {
  size_t tris = 0;
  for (auto _ : st) tris = cad::import_cad(data(file)).mesh.faces.size();
  st.counters["triangles"] = double(tris);
}
BENCHMARK_CAPTURE(BM_Import, step_panel, "02-PANEL.step")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Import, stl_panel, "02-PANEL.stl")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Import, obj_gearmotor, "04_37D-GEARMOTOR-50-70.obj")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Import, dae_gearmotor, "04_37D-GEARMOTOR-50-70.dae")
    ->Unit(benchmark::kMillisecond);

// Arg 0: points, Arg 1: threads.
void BM_SampleUniform(benchmark::State& st) {
  const TriMesh& m = mesh_100k();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(1));
  sampling::SamplingSettings s;
  s.count = size_t(st.range(0));
  for (auto _ : st) benchmark::DoNotOptimize(sampling::sample_uniform(m, s).points.data());
  st.SetItemsProcessed(st.iterations() * st.range(0));
  st.counters["triangles"] = double(m.faces.size());
}
BENCHMARK(BM_SampleUniform)
    ->Args({1000000, 1})
    ->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SamplePoisson(benchmark::State& st) {
  const TriMesh& m = mesh_100k();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(1));
  sampling::SamplingSettings s;
  s.count = size_t(st.range(0));
  s.method = sampling::Method::PoissonDisk;
  for (auto _ : st) benchmark::DoNotOptimize(sampling::sample_poisson_disk(m, s).points.data());
  st.SetItemsProcessed(st.iterations() * st.range(0));
}
BENCHMARK(BM_SamplePoisson)->Args({100000, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

// View-dependent: 1 M points visible from one swept line-scanner viewpoint (both shadow tests).
void BM_SampleVisible(benchmark::State& st) {
  const TriMesh& m = mesh_100k();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(1));
  sampling::ViewSettings v;
  const Eigen::Vector3d c = m.bbox().center().cast<double>(), top(c.x(), c.y(), m.bbox().max().z());
  v.T_mesh_sensor.push_back(look_at(top + Eigen::Vector3d(0, 0, 80), c));
  sampling::SamplingSettings s;
  s.count = size_t(st.range(0));
  for (auto _ : st) benchmark::DoNotOptimize(sampling::sample_visible(m, v, s).points.data());
  st.SetItemsProcessed(st.iterations() * st.range(0));
}
BENCHMARK(BM_SampleVisible)->Args({1000000, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
