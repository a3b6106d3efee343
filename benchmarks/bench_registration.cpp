// Registration speed on a 1 M-point scan (issue 4 target: median <= 1.5 s on 2 cores): the
// shipped USB scene, cut to its first profiles holding 1 M valid points, the plug registered with
// the default settings (ceres, gated RANSAC, the nominal pose as prior, segmentation on): one pass
// (BM_RegisterPlug1M), and as benchmarks/registration.yaml registers it, with the view re-sampled
// at the pose found and registered again (BM_RegisterPlug1MInView, register_in_view).
// Run: make bench-registration-speed -> reports/registration/.
#include <benchmark/benchmark.h>

#include "laserfit/registration/preprocess.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "laserfit/scan/reference.hpp"
#include "laserfit/scan/scanner.hpp"

using namespace laserfit;

namespace {

struct Fixture {
  PointCloud scan, ref;
  Pose nominal;
  Eigen::Vector3d viewpoint;
  TriMesh mesh;  // the plug's, to sample its view again
  scan::ScanSettings settings;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    const auto scene =
        scan::load_scene(std::string(LASERFIT_SOURCE_DIR) + "/datasets/scenes/usb_socket.yaml");
    const auto r = scan::simulate_scan(scene);
    // Whole profiles until 1 M valid points: an organized 1 M-point scan.
    const size_t W = size_t(r.cloud.width);
    size_t valid = 0, rows = 0;
    while (rows < size_t(r.cloud.height) && valid < 1000000) {
      for (size_t j = 0; j < W; ++j) valid += r.cloud.points[rows * W + j].allFinite();
      ++rows;
    }
    x.scan = r.cloud;
    x.scan.points.resize(rows * W), x.scan.labels.resize(rows * W), x.scan.height = int(rows);
    const auto& plug = scene.objects[1];
    x.nominal = plug.T_base_object;
    sampling::ViewSettings v;
    v.T_mesh_sensor.push_back(plug.T_base_object.inverse() *
                              r.T_base_sensor_nominal[r.cloud.height / 2]);
    v.geometry = scene.settings.sensor;
    sampling::SamplingSettings s;
    s.count = 60000;
    x.ref = sampling::sample_visible(plug.mesh, v, s);
    x.viewpoint = r.T_base_sensor_nominal[r.cloud.height / 2].translation();
    x.mesh = plug.mesh, x.settings = scene.settings;
    return x;
  }();
  return f;
}

registration::RegistrationSettings plug_settings(const Fixture& f) {
  registration::RegistrationSettings s;
  s.prior = f.nominal;
  s.q0 = Eigen::Quaterniond(f.nominal.rotation());
  s.pre.use_viewpoint = true, s.pre.viewpoint = f.viewpoint;
  return s;
}

void report(benchmark::State& st, const Fixture& f, const registration::RegistrationResult& r) {
  size_t valid = 0;
  for (const auto& p : f.scan.points) valid += p.allFinite();
  st.counters["scan_pts"] = double(valid);
  st.counters["ok"] = r.status == registration::Status::Ok;
  for (const auto& [k, v] : r.timings_s) st.counters[k + "_s"] = v;
}

void BM_RegisterPlug1M(benchmark::State& st) {
  const Fixture& f = fixture();
  const auto s = plug_settings(f);
  registration::RegistrationResult r;
  for (auto _ : st) r = registration::register_segmented(f.scan, f.ref, s);
  report(st, f, r);
}
BENCHMARK(BM_RegisterPlug1M)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

// Two registrations when the first finds a pose; the view sampling is timed as view_s.
void BM_RegisterPlug1MInView(benchmark::State& st) {
  const Fixture& f = fixture();
  const auto s = plug_settings(f);
  const registration::ViewSampler view = [&f](const Pose& T_scan_ref) {
    return scan::view_reference(f.mesh, T_scan_ref, f.settings, f.ref.points.size(), 0);
  };
  registration::RegistrationResult r;
  for (auto _ : st) r = registration::register_in_view(f.scan, f.ref, view, s);
  report(st, f, r);
}
BENCHMARK(BM_RegisterPlug1MInView)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

// The stages on the same scan, one at a time (where a registration's time goes).
void BM_StageSegment1M(benchmark::State& st) {  // register_segmented's clustering of the scan
  const Fixture& f = fixture();
  const double voxel = registration::auto_voxel_mm(f.ref);
  size_t parts = 0;
  for (auto _ : st) parts = registration::segment_clusters(f.scan, voxel, 3 * voxel, 20).size();
  st.counters["parts"] = double(parts);
}
BENCHMARK(BM_StageSegment1M)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(3);

void BM_StageCropNearPrior1M(benchmark::State& st) {  // the candidate part near the prior
  const Fixture& f = fixture();
  size_t n = 0;
  for (auto _ : st) n = registration::crop_near(f.scan, f.ref, f.nominal, 1.0).points.size();
  st.counters["points"] = double(n);
}
BENCHMARK(BM_StageCropNearPrior1M)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(3);

void BM_StageMixedPixels1M(benchmark::State& st) {
  const Fixture& f = fixture();
  for (auto _ : st) {
    PointCloud c = f.scan;
    benchmark::DoNotOptimize(registration::remove_mixed_pixels(c));
  }
}
BENCHMARK(BM_StageMixedPixels1M)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(3);

}  // namespace

BENCHMARK_MAIN();
