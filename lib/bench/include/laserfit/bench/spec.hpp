#pragma once
// A benchmark definition (benchmarks/*.yaml): which scenes and targets, which conditions (a grid
// or random draws over noise level, outlier rate, pose perturbation, prior error, sweep length),
// how many trials, the seed. Lengths mm, angles deg. Strict: unknown keys are errors.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "laserfit/core/enum_names.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/core/units.hpp"
#include "laserfit/metrics/pose_error.hpp"
#include "laserfit/registration/settings.hpp"

namespace laserfit::bench {

// Where a target's reference comes from: what the nominal sweep sees of its mesh, its whole
// surface (or reference_mesh's), or a file (recorded scenes).
enum class ReferenceSource { View, Full, Cloud };
// The point a target's true pose turns about (Target::pivot).
enum class Pivot { Origin, View, Centre };
// How trials are drawn: every combination of the axes' values, or random draws in their ranges.
enum class Sampling { Grid, Random };

struct Target {
  std::string object;  // the scene object whose pose is estimated
  metrics::Symmetry symmetry;
  double voxel_mm = 0;  // registration voxel; 0 = auto
  // view: what the nominal sweep sees | full: whole surface | cloud: a file (recorded scenes)
  ReferenceSource reference = ReferenceSource::View;
  std::string reference_mesh;  // another CAD file as the reference (a wrong-object trial)
  size_t reference_points = 60000;
  // view only: after a first pass, register again against the view sampled at the pose found
  // (registration::register_in_view; every method but `paper`, which is Algorithm 1 as published).
  bool resample_view = false;
  bool expect_failure = false;  // success = not `ok` (wrong object: must be rejected)
  // The point the true pose is rotated about (Conditions::rotation_deg). origin: the object
  // frame's origin. view: the centroid of what the nominal sweep sees of the object, so that the
  // seen part moves by at most translation_mm whatever the rotation; with a CAD origin far from
  // the seen part (a plate's corner), rotating about the origin sweeps the part out of view.
  // centre: the centre of the mesh's bounding box (a part turned in place whose CAD origin is,
  // say, an end face).
  Pivot pivot = Pivot::Origin;
  // turn_about (x|y|z, the scene's frame): the true pose turns about that axis through the pivot
  // by up to rotation_deg either way, not about a uniform random axis: a part resting on a table
  // lies anywhere turned about the vertical, and is never upside down.
  std::optional<Eigen::Vector3d> turn_about;
  // Degrees of freedom the view cannot fix, object frame: a nearly symmetric rotation (a needle's
  // spin about its shaft: only the eye breaks the symmetry) and a translation (a peg seen from
  // the side: its tip faces away). An `ambiguous` result that names one of them as unobservable
  // (and has no more unobservable directions than declared, a continuous symmetry counting one)
  // is a correct report: the rest of the pose is then scored without them.
  std::optional<Eigen::Vector3d> weak_rotation, weak_translation;
  // Recorded scenes only (docs/benchmark.md, "Recorded scenes"): the object's id in the scene's
  // scene_gt.json (BOP obj_id), its reference as a cloud file (reference: cloud) unless sampled
  // from reference_mesh (reference: full), the mesh MSSD is measured on (empty: the reference's
  // points) and the scan label of its points (-1: the scans carry none).
  int obj_id = -1;
  std::string reference_cloud, model;
  int label = -1;
};

struct SceneCase {
  std::string name;
  std::string scene_path;  // simulated: the scan scene (YAML) every trial scans
  // Recorded: a folder of a lab's own scans, scans/<image id>.pcd|.ply, with scene_gt.json
  // (BOP layout: T_scan_object per image and obj_id, mm) and optionally scene_prior.json (the
  // same layout: the pose the cell believed; without it every method registers with no prior).
  std::string recorded_dir;
  Unit unit = Unit::Millimetre;  // recorded: of scans, references and models stating none
  // Recorded: image id -> obj_id -> T_scan_object, measured (scene_gt.json; one trial per image,
  // ascending) and believed (scene_prior.json, if there is one). Read once, when the file loads.
  std::map<int, std::map<int, Pose>> truth, prior;
  bool has_prior = false;
  // prior: none — every method registers with no prior, globally: a lab's first scan of a new
  // part (issue: registration without a prior). Simulated scenes otherwise start from the nominal
  // pose (or Conditions::prior_*); recorded ones from scene_prior.json, which this ignores.
  bool use_prior = true;
  bool recorded() const { return !recorded_dir.empty(); }
  std::vector<Target> targets;
};

// The conditions a trial runs under. Each is an axis of the benchmark's grid (or a range of its
// random draws); the defaults are the scene's own settings.
struct Conditions {
  double noise_scale = 1;          // x the sensor's noise sigmas (depth, jitter, speckle, bias)
  double outlier_rate = -1;        // outliers per point on every surface; < 0: the scene's own
  double rotation_deg = 20;        // true pose: rotated up to this from the nominal (uniform axis)
  double translation_mm = 1;       //   and moved up to this (uniform in a ball)
  double prior_rotation_deg = -1;  // prior: the nominal pose (< 0), or the truth rotated up to
  double prior_translation_mm =
      -1;                     //   this and moved up to this (independent of the perturbation)
  double sweep_fraction = 1;  // sweep length x this about its centre (low overlap below 1)
};
// Names of the axes, in the order of Conditions (YAML keys, CSV columns).
const std::vector<std::string>& axis_names();
double& axis(Conditions& c, const std::string& name);
double axis(const Conditions& c, const std::string& name);

struct Benchmark {
  std::string name, file;
  uint64_t seed = 1;
  int trials = 10;  // per grid cell (grid) or in total per scene (random); recorded: one per scan
  Sampling mode = Sampling::Grid;
  std::map<std::string, std::vector<double>> axes;  // grid: values; random: [min, max]
  double t_tol_mm = 0.05, r_tol_deg = 0.5;          // success tolerance
  std::vector<registration::Method> methods = {registration::Method::Ceres};  // `laserfit bench`'s
  std::vector<SceneCase> scenes;
  uint64_t digest = 0;  // of the file's bytes: a resumed run must use the same file
};

Benchmark load_benchmark(const std::string& path);  // throws laserfit::Error naming the file

// Indices of the named scenes (all when `names` is empty); an unknown name throws, listing the
// benchmark's scenes.
std::vector<int> scene_indices(const Benchmark& b, const std::vector<std::string>& names);

}  // namespace laserfit::bench

namespace laserfit {
template <>
struct EnumNames<bench::ReferenceSource> {
  static constexpr const char* what = "reference";
  static constexpr std::pair<bench::ReferenceSource, const char*> table[] = {
      {bench::ReferenceSource::View, "view"},
      {bench::ReferenceSource::Full, "full"},
      {bench::ReferenceSource::Cloud, "cloud"}};
};
template <>
struct EnumNames<bench::Pivot> {
  static constexpr const char* what = "pivot";
  static constexpr std::pair<bench::Pivot, const char*> table[] = {
      {bench::Pivot::Origin, "origin"},
      {bench::Pivot::View, "view"},
      {bench::Pivot::Centre, "centre"}};
};
template <>
struct EnumNames<bench::Sampling> {
  static constexpr const char* what = "mode";
  static constexpr std::pair<bench::Sampling, const char*> table[] = {
      {bench::Sampling::Grid, "grid"}, {bench::Sampling::Random, "random"}};
};
}  // namespace laserfit
