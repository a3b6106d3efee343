#include "laserfit/scan/scanner.hpp"

#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "laserfit/core/error.hpp"
#include "laserfit/core/rng.hpp"
#include "laserfit/raycast/scene.hpp"
#include "noise.hpp"

namespace laserfit::scan {
namespace {

using Clock = std::chrono::steady_clock;
constexpr uint64_t kStreamProfile = 0x5CA1, kStreamGlobal = 0x5CA2;

Pose twist(const Eigen::Vector3d& t_mm, const Eigen::Vector3d& r_rad) {
  Pose T = Pose::Identity();
  const double a = r_rad.norm();
  if (a > 0) T.linear() = Eigen::AngleAxisd(a, r_rad / a).toRotationMatrix();
  T.translation() = t_mm;
  return T;
}

Eigen::Vector3d gauss3(std::mt19937_64& g, double sigma) {
  return {gauss(g) * sigma, gauss(g) * sigma, gauss(g) * sigma};
}

// Smooth per-profile deviation of the carrying arm: AR(1) per component, stationary sigma.
std::vector<Pose> motion_jitter(const MotionSettings& m, int profiles, std::mt19937_64& g) {
  std::vector<Pose> J(profiles, Pose::Identity());
  if (!m.enabled || (m.jitter_sigma_mm == 0 && m.jitter_sigma_deg == 0)) return J;
  const double rho = std::exp(-1.0 / m.jitter_corr_profiles), k = std::sqrt(1 - rho * rho);
  const double st = m.jitter_sigma_mm, sr = m.jitter_sigma_deg * M_PI / 180.0;
  Eigen::Vector3d t = gauss3(g, st), r = gauss3(g, sr);
  for (int i = 0; i < profiles; ++i) {
    if (i > 0) t = rho * t + k * gauss3(g, st), r = rho * r + k * gauss3(g, sr);
    J[i] = twist(t, r);
  }
  return J;
}

struct Atomics {
  std::atomic<size_t> rays{0}, hits{0}, valid{0}, range{0}, grazing{0}, camera{0}, drop{0}, out{0},
      mixed{0};
  std::atomic<int64_t> laser_ns{0}, camera_ns{0}, noise_ns{0};
};

int64_t ns_since(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t).count();
}

}  // namespace

ScanResult simulate_scan(const ScanScene& sc) {
  const auto t_start = Clock::now();
  const ScanSettings& s = sc.settings;
  s.validate(sc.file.empty() ? "scan settings" : sc.file);
  if (sc.objects.empty()) throw Error(sc.file, "scene has no objects");
  const auto& g = s.sensor;
  const int W = g.points_per_profile, H = s.sweep.profiles();

  raycast::Scene scene;
  for (const auto& o : sc.objects) scene.add_mesh(o.mesh, o.T_base_object);
  scene.commit();
  ScanResult r;
  r.seed = sc.seed;
  r.timings.bvh_s = std::chrono::duration<double>(Clock::now() - t_start).count();

  // Per-scan draws (one generator, fixed order): rigid arm error, depth bias, jitter sequence.
  auto global = block_rng(sc.seed, kStreamGlobal, 0);
  const auto& m = s.motion;
  Pose E_offset = Pose::Identity(), E_calib = Pose::Identity();
  const Eigen::Vector3d off_t = gauss3(global, m.offset_sigma_mm);
  const Eigen::Vector3d off_r = gauss3(global, m.offset_sigma_deg * M_PI / 180.0);
  const double bias = gauss(global) * s.noise.bias_sigma_um * 1e-3;
  if (m.enabled) {
    E_offset = twist(off_t, off_r);
    const auto& c = m.calibration_error;
    E_calib = twist({c[0], c[1], c[2]}, Eigen::Vector3d(c[3], c[4], c[5]) * M_PI / 180.0);
  }
  const std::vector<Pose> J = motion_jitter(m, H, global);

  r.T_base_sensor_nominal.resize(H);
  r.T_base_sensor_true.resize(H);
  for (int i = 0; i < H; ++i) {
    Pose step = Pose::Identity();
    step.translation() = s.sweep.direction * (i * s.sweep.spacing_mm());
    r.T_base_sensor_nominal[i] = s.sweep.T_base_sensor_start * step;
    r.T_base_sensor_true[i] = E_offset * r.T_base_sensor_nominal[i] * J[i] * E_calib;
  }
  std::vector<Eigen::Vector3d> ray_dir(W);
  for (int j = 0; j < W; ++j) ray_dir[j] = g.ray_direction(j);
  const float t_max = static_cast<float>(g.z_max_mm / std::cos(g.half_fan_rad()) + 1.0);

  const float nan = std::numeric_limits<float>::quiet_NaN();
  r.cloud.points.assign(size_t(W) * H, Eigen::Vector3f::Constant(nan));
  r.cloud.labels.assign(size_t(W) * H, -1);
  r.raw.points.assign(size_t(W) * H, Eigen::Vector3f::Constant(nan));
  Atomics a;

  tbb::parallel_for(0, H, [&](int i) {
    const Pose& Tt = r.T_base_sensor_true[i];
    const sensor::LineScannerView view(Tt, g, /*swept=*/false);
    auto t0 = Clock::now();
    // 1. Laser fan: first surface along each ray = the lit point (laser shadows are implicit).
    const Eigen::Vector3f origin = Tt.translation().cast<float>();
    std::vector<Eigen::Vector3f> dirs(W);
    for (int j = 0; j < W; ++j) dirs[j] = (Tt.linear() * ray_dir[j]).cast<float>();
    std::vector<raycast::Hit> hits;
    scene.intersect_fan(origin, dirs, 0.f, t_max, hits);
    std::vector<Sample> prof(W);
    std::vector<int> label(W, -1);
    std::vector<Eigen::Vector3f> from(W), to(W);
    std::vector<uint8_t> check(W, 0), clear(W, 1);
    const Eigen::Vector3f camera = view.camera_in_scene();
    size_t n_hits = 0, n_range = 0, n_graze = 0, n_cam = 0;
    for (int j = 0; j < W; ++j) {
      const raycast::Hit& h = hits[j];
      if (!h.valid()) continue;
      ++n_hits;
      const double z = h.t * ray_dir[j].z();
      if (z < g.z_min_mm || z > g.z_max_mm) {
        ++n_range;
        continue;
      }
      const double cos_inc = -h.normal.dot(dirs[j]);
      if (cos_inc < view.cos_max_incidence()) {
        ++n_graze;
        continue;
      }
      const Eigen::Vector3f p = origin + h.t * dirs[j];
      if (!view.camera_angle_ok(p, h.normal, camera)) {
        ++n_cam;
        continue;
      }
      prof[j] = {true,    h.t * ray_dir[j].x(),    z, ray_dir[j].x(), ray_dir[j].z(),
                 cos_inc, sc.objects[h.geom].shiny};
      label[j] = h.geom;
      from[j] = p + sensor::kSelfShadowEps_mm * h.normal;
      to[j] = camera;
      check[j] = 1;
    }
    a.laser_ns += ns_since(t0);
    // 2. Camera shadow: the camera must see the lit point.
    t0 = Clock::now();
    scene.segments_clear(from, to, check, sensor::kSelfShadowEps_mm, clear);
    for (int j = 0; j < W; ++j)
      if (check[j] && !clear[j]) prof[j].valid = false, label[j] = -1, ++n_cam;
    a.camera_ns += ns_since(t0);
    // 3. Noise, then report through the nominal pose (the robot's belief).
    t0 = Clock::now();
    ScanStats st;
    if (s.noise.enabled) {
      auto rng = block_rng(sc.seed, kStreamProfile, uint64_t(i));
      apply_noise(prof, s.noise, g, bias, rng, st);
    }
    const Pose& Tn = r.T_base_sensor_nominal[i];
    size_t n_valid = 0;
    for (int j = 0; j < W; ++j) {
      if (!prof[j].valid) continue;
      ++n_valid;
      const Eigen::Vector3d ps(prof[j].x, 0.0, prof[j].z);
      const size_t k = size_t(i) * W + j;
      r.raw.points[k] = ps.cast<float>();
      r.cloud.points[k] = (Tn * ps).cast<float>();
      r.cloud.labels[k] = label[j];
    }
    a.noise_ns += ns_since(t0);
    a.rays += W, a.hits += n_hits, a.valid += n_valid, a.range += n_range, a.grazing += n_graze;
    a.camera += n_cam, a.drop += st.dropouts, a.out += st.outliers, a.mixed += st.mixed_pixels;
  });

  r.cloud.width = r.raw.width = W;
  r.cloud.height = r.raw.height = H;
  r.stats = {a.rays, a.hits, a.valid, a.range, a.grazing, a.camera, a.drop, a.out, a.mixed};
  const int mid = H / 2;
  for (const auto& o : sc.objects)
    r.T_scan_object.push_back(r.T_base_sensor_nominal[mid] * r.T_base_sensor_true[mid].inverse() *
                              o.T_base_object);
  r.cloud.metadata["seed"] = r.raw.metadata["seed"] = std::to_string(sc.seed);
  r.cloud.metadata["frame"] = "base (nominal sensor poses)";
  r.raw.metadata["frame"] = "sensor, per profile (x along the line, z depth)";
  r.cloud.metadata["unit"] = r.raw.metadata["unit"] = "mm";
  if (!sc.file.empty()) r.cloud.metadata["scene"] = r.raw.metadata["scene"] = sc.file;
  r.cloud.metadata["noise"] = s.noise.enabled ? "on" : "off";
  // Where the sensor was (mid-sweep, nominal): registration orients scan normals towards it.
  r.cloud.sensor_origin = r.T_base_sensor_nominal[mid].translation();
  r.timings.laser_s = a.laser_ns * 1e-9;
  r.timings.camera_s = a.camera_ns * 1e-9;
  r.timings.noise_s = a.noise_ns * 1e-9;
  r.timings.total_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  return r;
}

}  // namespace laserfit::scan
