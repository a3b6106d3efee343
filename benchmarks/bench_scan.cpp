// Scan synthesis speed (issue target: a 2048 x 1000-profile scan of a 100 k-triangle scene with
// both shadow tests in <= 0.1 s on 2 cores; the real sensor makes 2048 x 10 kHz = 20.5 M points/s).
// Run: make bench-scan -> reports/scan/.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "bench_meshes.hpp"
#include "laserfit/scan/scanner.hpp"

using namespace laserfit;

namespace {

// The 100 k-triangle gear motor lying on its side (axis along x); the scanner 88 mm above the
// top of its cylindrical body, laser line along the axis, sweeping 20 mm across it in 1000
// profiles, so that nearly every ray hits and needs both the laser and the camera test.
scan::ScanScene gearmotor_scene(bool noise) {
  scan::ScanScene sc;
  const TriMesh& m = bench::mesh_100k();
  const Pose lying = pose_from_tq(
      {0, 0, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())));
  sc.objects.push_back({"gearmotor", "", lying, true, m});
  TriMesh placed = m;
  placed.transform(lying.cast<float>());
  const Eigen::Vector3d c = placed.bbox().center().cast<double>();
  const double top = placed.bbox().max().z();
  auto& sw = sc.settings.sweep;
  sw.T_base_sensor_start = look_at({c.x(), c.y() + 10, top + 88}, {c.x(), c.y() + 10, top});
  // look_at's sensor y is base -y: the sweep runs from y = +10 to y = -10 across the cylinder.
  sw.length_mm = 19.98, sw.speed_mm_s = 20, sw.profile_rate_hz = 1000;  // 1000 profiles
  sc.settings.noise.enabled = sc.settings.motion.enabled = noise;
  return sc;
}

// Arg 0: threads, Arg 1: noise on.
void BM_Scan(benchmark::State& st) {
  const auto sc = gearmotor_scene(st.range(1) != 0);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(0));
  scan::ScanResult r;
  double laser = 0, camera = 0, noise = 0, bvh = 0;
  for (auto _ : st) {
    r = scan::simulate_scan(sc);
    laser += r.timings.laser_s, camera += r.timings.camera_s, noise += r.timings.noise_s,
        bvh += r.timings.bvh_s;
  }
  const double n = double(st.iterations());
  st.SetItemsProcessed(int64_t(st.iterations() * r.stats.rays));
  st.counters["profiles"] = r.cloud.height;
  st.counters["valid_pts"] = double(r.stats.valid);
  st.counters["cam_rays"] = double(r.stats.valid + r.stats.camera_shadow);
  st.counters["bvh_ms"] = 1e3 * bvh / n;
  st.counters["laser_cpu_ms"] = 1e3 * laser / n;
  st.counters["camera_cpu_ms"] = 1e3 * camera / n;
  st.counters["noise_cpu_ms"] = 1e3 * noise / n;
}
BENCHMARK(BM_Scan)
    ->Args({1, 1})
    ->Args({2, 1})
    ->Args({2, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
