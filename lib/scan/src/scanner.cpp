#include "laserfit/scan/scanner.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>

#include "laserfit/core/big_buffer.hpp"
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

Eigen::Vector3d gauss3(Mt19937_64& g, double sigma) {
  return {gauss(g) * sigma, gauss(g) * sigma, gauss(g) * sigma};
}

// Smooth per-profile deviation of the carrying arm: AR(1) per component, stationary sigma.
std::vector<Pose> motion_jitter(const MotionSettings& m, int profiles, Mt19937_64& g) {
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

// The per-scan draws (one generator, fixed order): rigid arm error, depth bias, jitter. Fills the
// nominal (believed) and true sensor pose of every profile; returns the depth bias (mm).
double sensor_poses(const ScanSettings& s, uint64_t seed, ScanResult& r) {
  auto global = block_rng(seed, kStreamGlobal, 0);
  const auto& m = s.motion;
  const int H = s.sweep.profiles();
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
  return bias;
}

// One profile's working memory, kept per thread: a scan has thousands of profiles.
struct Profile {
  std::vector<Eigen::Vector3f> dirs, from, to;
  std::vector<raycast::Hit> hits;
  std::vector<Sample> samples;
  std::vector<int> label;
  std::vector<uint8_t> check, clear;
  ScanStats stats;

  void reset(int W) {
    dirs.resize(W), from.resize(W), to.resize(W);
    samples.assign(W, Sample{});
    label.assign(W, -1);
    check.assign(W, 0), clear.assign(W, 1);
    stats = ScanStats{};
  }
};

struct Counters {
  std::atomic<size_t> rays{0}, hits{0}, valid{0}, range{0}, grazing{0}, camera{0}, drop{0}, out{0},
      mixed{0};
  std::atomic<int64_t> laser_ns{0}, camera_ns{0}, noise_ns{0};

  void add(const ScanStats& s) {
    rays += s.rays, hits += s.hits, valid += s.valid, range += s.out_of_range;
    grazing += s.grazing, camera += s.camera_shadow, drop += s.dropouts, out += s.outliers;
    mixed += s.mixed_pixels;
  }
  ScanStats total() const { return {rays, hits, valid, range, grazing, camera, drop, out, mixed}; }
};

int64_t ns_since(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t).count();
}

// What is fixed for a whole scan: the scene, the sensor and the fan of ray directions.
struct Setup {
  const ScanScene& sc;
  const raycast::Scene& scene;
  std::vector<Eigen::Vector3d> ray_dir;  // sensor frame
  float t_max = 0;
  double bias_mm = 0;
};

// 1. Laser fan: the first surface along each ray is the lit point (laser shadows are implicit);
// kept if in the depth range, not too grazing and inside the camera's angle.
void light(const Setup& u, const Pose& Tt, Profile& p) {
  const auto& g = u.sc.settings.sensor;
  const int W = g.points_per_profile;
  const sensor::LineScannerView view(Tt, g, /*swept=*/false);
  const Eigen::Vector3f origin = Tt.translation().cast<float>();
  for (int j = 0; j < W; ++j) p.dirs[j] = (Tt.linear() * u.ray_dir[j]).cast<float>();
  u.scene.intersect_fan(origin, p.dirs, 0.f, u.t_max, p.hits);
  const Eigen::Vector3f camera = view.camera_in_scene();
  p.stats.rays = W;
  for (int j = 0; j < W; ++j) {
    const raycast::Hit& h = p.hits[j];
    if (!h.valid()) continue;
    ++p.stats.hits;
    const Eigen::Vector3d& d = u.ray_dir[j];
    const double z = h.t * d.z();
    if (z < g.z_min_mm || z > g.z_max_mm) {
      ++p.stats.out_of_range;
      continue;
    }
    const double cos_inc = -h.normal.dot(p.dirs[j]);
    if (cos_inc < view.cos_max_incidence()) {
      ++p.stats.grazing;
      continue;
    }
    const Eigen::Vector3f x = origin + h.t * p.dirs[j];
    if (!view.camera_angle_ok(x, h.normal, camera)) {
      ++p.stats.camera_shadow;
      continue;
    }
    p.samples[j] = {true, h.t * d.x(), z, d.x(), d.z(), cos_inc, u.sc.objects[h.geom].shiny};
    p.label[j] = h.geom;
    p.from[j] = x + sensor::kSelfShadowEps_mm * h.normal;
    p.to[j] = camera;
    p.check[j] = 1;
  }
}

// 2. Camera shadow: the camera must see the lit point.
void shade(const Setup& u, Profile& p) {
  u.scene.segments_clear(p.from, p.to, p.check, sensor::kSelfShadowEps_mm, p.clear);
  for (size_t j = 0; j < p.check.size(); ++j)
    if (p.check[j] && !p.clear[j])
      p.samples[j].valid = false, p.label[j] = -1, ++p.stats.camera_shadow;
}

// 3. Noise, then report through the nominal pose (the robot's belief). Writes the whole row
// (NaN and label -1 where there is no measurement).
void report(const Setup& u, int i, Profile& p, ScanResult& r) {
  const auto& s = u.sc.settings;
  if (s.noise.enabled) {
    auto rng = block_rng(u.sc.seed, kStreamProfile, uint64_t(i));
    apply_noise(p.samples, s.noise, s.sensor, u.bias_mm, rng, p.stats);
  }
  const Pose& Tn = r.T_base_sensor_nominal[i];
  const Eigen::Vector3f nan = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  const size_t W = p.samples.size(), row = size_t(i) * W;
  for (size_t j = 0; j < W; ++j) {
    const Sample& m = p.samples[j];
    const size_t k = row + j;
    if (!m.valid) {
      r.raw.points[k] = r.cloud.points[k] = nan, r.cloud.labels[k] = -1;
      continue;
    }
    ++p.stats.valid;
    const Eigen::Vector3d ps(m.x, 0.0, m.z);
    r.raw.points[k] = ps.cast<float>();
    r.cloud.points[k] = (Tn * ps).cast<float>();
    r.cloud.labels[k] = p.label[j];
  }
}

void scan_profiles(const Setup& u, ScanResult& r) {
  const int W = u.sc.settings.sensor.points_per_profile, H = u.sc.settings.sweep.profiles();
  // Every row is written by its profile, in parallel: no serial first pass over the output.
  resize_advised(r.cloud.points, size_t(W) * H);
  resize_advised(r.raw.points, size_t(W) * H);
  resize_advised(r.cloud.labels, size_t(W) * H);
  tbb::enumerable_thread_specific<Profile> work;
  Counters c;
  tbb::parallel_for(0, H, [&](int i) {
    Profile& p = work.local();
    p.reset(W);
    auto t0 = Clock::now();
    light(u, r.T_base_sensor_true[i], p);
    c.laser_ns += ns_since(t0);
    t0 = Clock::now();
    shade(u, p);
    c.camera_ns += ns_since(t0);
    t0 = Clock::now();
    report(u, i, p, r);
    c.noise_ns += ns_since(t0);
    c.add(p.stats);
  });
  r.stats = c.total();
  r.timings.laser_s = c.laser_ns * 1e-9;
  r.timings.camera_s = c.camera_ns * 1e-9;
  r.timings.noise_s = c.noise_ns * 1e-9;
}

void describe(const ScanScene& sc, ScanResult& r) {
  const auto& s = sc.settings;
  r.cloud.width = r.raw.width = s.sensor.points_per_profile;
  r.cloud.height = r.raw.height = s.sweep.profiles();
  const int mid = r.cloud.height / 2;
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
}

}  // namespace

ScanResult simulate_scan(const ScanScene& sc) {
  const auto t_start = Clock::now();
  const ScanSettings& s = sc.settings;
  s.validate(sc.file.empty() ? "scan settings" : sc.file);
  if (sc.objects.empty()) throw Error(sc.file, "scene has no objects");
  raycast::Scene scene;
  for (const auto& o : sc.objects) scene.add_mesh(o.mesh, o.T_base_object);
  scene.commit();
  ScanResult r;
  r.seed = sc.seed;
  r.timings.bvh_s = std::chrono::duration<double>(Clock::now() - t_start).count();

  const auto& g = s.sensor;
  Setup u{sc, scene, std::vector<Eigen::Vector3d>(g.points_per_profile)};
  for (int j = 0; j < g.points_per_profile; ++j) u.ray_dir[j] = g.ray_direction(j);
  u.t_max = static_cast<float>(g.z_max_mm / std::cos(g.half_fan_rad()) + 1.0);
  u.bias_mm = sensor_poses(s, sc.seed, r);
  scan_profiles(u, r);
  describe(sc, r);
  r.timings.total_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  return r;
}

}  // namespace laserfit::scan
