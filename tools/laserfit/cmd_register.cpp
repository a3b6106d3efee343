// laserfit register --scan S.pcd --ref R.pcd [--ref R2.pcd ...]: pose of each reference in the
// scan (the paper's Algorithm 1 and variants), with fit statistics, covariance and a trust status.
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>

#include "command.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/units.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/registration/thresholds.hpp"

namespace laserfit::cli {
namespace {

struct Options {
  std::string scan, unit = "mm", fail_on, method = "ceres", coarse, viewpoint, thresholds, object,
                    thin = "auto";
  std::string weak_rotation, weak_translation;  // x | y | z of the reference frame
  double thin_axis_sigma = registration::ThinSettings{}.axis_prior_deg;
  double max_sigma_um = registration::TrustSettings{}.max_sigma_mm * 1e3;
  double max_sigma_deg = registration::TrustSettings{}.max_sigma_deg;
  CLI::App* app = nullptr;                     // to tell the options given from the defaults
  std::vector<std::string> refs, priors, q0s;  // --prior / --q0: one for all, or one per --ref
  double voxel = 0, rho_rot = 30, rho_icp = 0.05;
  int attempts = 8;
  int jobs = 0;
  uint64_t seed = 1;
  bool json = false, no_segment = false, refine_only = false;
  int max_clusters = 4;
};

Eigen::Vector3d parse_vec3(const std::string& text, const std::string& what) {
  std::string t = text;
  for (char& c : t)
    if (c == ',') c = ' ';
  std::istringstream in(t);
  Eigen::Vector3d v;
  if (!(in >> v.x() >> v.y() >> v.z()) || !v.allFinite())
    throw Error(what + ": expected 'x y z' (mm)");
  return v;
}

Eigen::Quaterniond parse_q0(const std::string& text) {
  std::istringstream in(text);
  double w, x, y, z;
  if (!(in >> w >> x >> y >> z)) throw Error("--q0: expected 'w x y z'");
  const Eigen::Quaterniond q(w, x, y, z);
  if (!(std::abs(q.norm() - 1) <= 1e-3)) throw Error("--q0: not a unit quaternion");
  return q.normalized();
}

// One value for every reference, or one per --ref in order: parsed, as many as there are refs.
template <class Parse>
auto per_reference(const std::vector<std::string>& given, size_t refs, const std::string& option,
                   Parse parse) -> std::vector<std::optional<decltype(parse(given[0]))>> {
  std::vector<std::optional<decltype(parse(given[0]))>> out(refs);
  if (given.empty()) return out;
  if (given.size() != 1 && given.size() != refs)
    throw Error(option + " given " + std::to_string(given.size()) + " times for " +
                std::to_string(refs) + " references: give one for all, or one per --ref in order");
  for (size_t i = 0; i < refs; ++i) out[i] = parse(given[given.size() == 1 ? 0 : i]);
  return out;
}

io::Json result_json(const std::string& ref, const registration::RegistrationResult& r) {
  io::Json cov = io::Json::array();
  for (int i = 0; i < 6; ++i) {
    io::Json row = io::Json::array();
    for (int j = 0; j < 6; ++j) row.push_back(r.covariance(i, j));
    cov.push_back(row);
  }
  return {{"ref", ref},
          {"status", registration::status_name(r.status)},
          {"reason", r.reason},
          {"T_scan_ref", io::pose_to_json(r.T_scan_ref)},
          {"fitness_mm2", r.fitness_mm2},
          {"inlier_rmse_um", r.inlier_rmse_mm * 1e3},
          {"residual_sigma_um", r.residual_sigma_mm * 1e3},
          {"overlap", r.overlap},
          {"attempts", r.attempts},
          {"iterations", r.iterations},
          {"voxel_mm", r.voxel_mm},
          {"covariance", cov},
          {"covariance_order", "rx ry rz (rad, about the matched points' centroid), tx ty tz (mm)"},
          {"sigma_origin_um", r.sigma_origin_mm * 1e3},
          {"sigma_rotation_deg", r.sigma_rotation_deg},
          {"hessian_eigenvalues",
           std::vector<double>(r.hessian_eigenvalues.data(), r.hessian_eigenvalues.data() + 6)},
          {"weakest_direction",  // [rotation x the radius below; translation], scan frame
           std::vector<double>(r.weakest_direction.data(), r.weakest_direction.data() + 6)},
          {"hessian_centre_mm", {r.hessian_centre.x(), r.hessian_centre.y(), r.hessian_centre.z()}},
          {"hessian_radius_mm", r.hessian_radius_mm},
          {"timings_s", r.timings_s},
          {"log", r.log}};
}

// Three lines per reference: status, pose, fit.
std::string human_text(const std::string& ref_path, const registration::RegistrationResult& r) {
  const auto tq = pose_to_tq(r.T_scan_ref);
  std::ostringstream h;
  h << ref_path << ": " << registration::status_name(r.status)
    << (r.reason.empty() ? "" : " (" + r.reason + ")") << "\n  T_scan_ref  t = [" << tq[0] << ", "
    << tq[1] << ", " << tq[2] << "] mm, q = [" << tq[3] << ", " << tq[4] << ", " << tq[5] << ", "
    << tq[6] << "]\n  fit         rmse " << r.inlier_rmse_mm * 1e3 << " um, overlap " << r.overlap
    << ", " << r.attempts << " attempt(s)\n";
  return h.str();
}

int run(const Options& o) {
  const Unit unit = parse_unit(o.unit);
  const double to_mm = unit_to_mm(unit);
  const PointCloud scan = io::read_cloud(o.scan, unit);
  registration::RegistrationSettings s;
  registration::apply_method(s, parse_enum<registration::Method>(o.method));
  if (!o.coarse.empty()) s.coarse.method = parse_enum<registration::CoarseMethod>(o.coarse);
  s.pre.voxel_mm = o.voxel;
  s.rho_rot_deg = o.rho_rot;
  s.rho_icp_vox2 = o.rho_icp;
  std::optional<registration::Thresholds> tuned;
  if (!o.thresholds.empty()) tuned = registration::load_thresholds(o.thresholds);
  // Tuned thresholds replace the defaults; options given on the command line still win.
  auto given = [&](const char* opt) { return o.app->count(opt) > 0; };
  auto settings_for = [&](const std::string& object) {
    registration::RegistrationSettings x = s;
    if (!tuned) return x;
    tuned->apply(x, object, o.voxel);
    if (given("--method"))
      registration::apply_method(x, parse_enum<registration::Method>(o.method));
    if (given("--coarse")) x.coarse.method = s.coarse.method;
    if (given("--voxel")) x.pre.voxel_mm = o.voxel;
    if (given("--rho-rot")) x.rho_rot_deg = o.rho_rot;
    if (given("--rho-icp")) x.rho_icp_vox2 = o.rho_icp;
    return x;
  };
  s.max_attempts = o.attempts;
  s.segment.enabled = !o.no_segment, s.segment.max_clusters = o.max_clusters;
  s.seed = o.seed;
  s.thin.mode = parse_enum<registration::ThinMode>(o.thin),
  s.thin.axis_prior_deg = o.thin_axis_sigma;
  s.trust.weak_rotation = registration::named_axis(o.weak_rotation);
  s.trust.weak_translation = registration::named_axis(o.weak_translation);
  s.trust.max_sigma_mm = o.max_sigma_um * 1e-3, s.trust.max_sigma_deg = o.max_sigma_deg;
  const auto priors = per_reference(o.priors, o.refs.size(), "--prior", [&](const std::string& t) {
    Pose T = parse_pose(t, "--prior");
    T.translation() *= to_mm;
    return T;
  });
  const auto q0s = per_reference(o.q0s, o.refs.size(), "--q0", parse_q0);
  if (!o.viewpoint.empty())
    s.pre.use_viewpoint = true, s.pre.viewpoint = parse_vec3(o.viewpoint, "--viewpoint") * to_mm;
  else if (scan.sensor_origin)
    s.pre.use_viewpoint = true, s.pre.viewpoint = *scan.sensor_origin;

  io::Json results = io::Json::array();
  std::ostringstream h;
  for (size_t i = 0; i < o.refs.size(); ++i) {
    const std::string& ref_path = o.refs[i];
    const PointCloud ref = io::read_cloud(ref_path, unit);
    registration::RegistrationSettings rs = settings_for(
        !o.object.empty() ? o.object : std::filesystem::path(ref_path).stem().string());
    rs.prior = priors[i], rs.q0 = q0s[i], rs.skip_coarse = o.refine_only && priors[i];
    registration::RegistrationResult r;
    try {
      r = registration::register_scan(scan, ref, rs);
    } catch (const Error& e) {
      throw Error(o.scan + " vs " + ref_path, e.what());
    }
    results.push_back(result_json(ref_path, r));
    results.back()["cluster"] = r.part;
    h << human_text(ref_path, r);
  }
  bool refused = false;  // --fail-on: a status scripts must not act on
  for (const auto& r : results)
    refused |= r["status"] == "failed" || (o.fail_on == "ambiguous" && r["status"] == "ambiguous");
  emit(o.json,
       io::Json{{"scan", o.scan},
                {"scan_unit", scan.metadata.count("unit_converted_from")
                                  ? scan.metadata.at("unit_converted_from")
                                  : "mm"},
                {"method", o.method},
                {"seed", o.seed},
                {"thresholds", o.thresholds},
                {"results", results}},
       h.str());
  return !o.fail_on.empty() && refused ? tools::kNotTrusted : tools::kDone;
}

}  // namespace

Command add_register(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "register",
      "Estimate the pose of each reference cloud in a scan (paper's Algorithm 1: FPFH + "
      "RANSAC, orientation gate, ICP loop) with fitness, covariance and ok/ambiguous/failed.");
  app->add_option("--scan", o->scan, "scan cloud (.pcd/.ply), mm; NaN points are ignored")
      ->required();
  app->add_option("--ref", o->refs, "reference cloud with normals (laserfit refcloud); repeatable")
      ->required();
  tools::add_unit_option(
      *app, "--unit", o->unit,
      "unit of the clouds that do not state one (laserfit's own files say mm) and of "
      "--prior and --viewpoint; results are always mm");
  app->add_option("--method", o->method,
                  "method: " + join(names_of<registration::Method>()) +
                      " (paper: Algorithm 1 as published, PCL's RANSAC and ICP)")
      ->check(CLI::IsMember(names_of<registration::Method>()))
      ->capture_default_str();
  app->add_option("--coarse", o->coarse,
                  "coarse stage: gated (rho_rot tested on every RANSAC hypothesis) | pcl (PCL "
                  "SampleConsensusPrerejective, rho_rot on its result; the default of paper)")
      ->check(CLI::IsMember(names_of<registration::CoarseMethod>()));
  app->add_option("--prior", o->priors,
                  "prior pose T_scan_ref 'x y z qw qx qy qz' (e.g. from the arm), once for every "
                  "--ref or once per --ref in their order: the first "
                  "hypothesis, RANSAC after it");
  app->add_flag("--refine-only", o->refine_only, "with --prior: refine from it, no RANSAC");
  app->add_option("--q0", o->q0s,
                  "prior orientation 'w x y z' for the rho_rot gate (paper's q0); once, or once "
                  "per --ref");
  app->add_option("--rho-rot", o->rho_rot, "rho_rot: reject RANSAC poses farther from q0 (deg)")
      ->capture_default_str();
  app->add_option("--rho-icp", o->rho_icp, "rho_ICP: stop below this fitness, in voxel^2")
      ->capture_default_str();
  app->add_option("--attempts", o->attempts, "RANSAC + ICP rounds at most")->capture_default_str();
  app->add_option("--voxel", o->voxel, "voxel size (mm); 0 = reference diagonal / 150")
      ->capture_default_str();
  app->add_option("--viewpoint", o->viewpoint,
                  "sensor position 'x y z' in the scan frame (default: from the scan's header)");
  app->add_option("--seed", o->seed, "RANSAC seed")->capture_default_str();
  app->add_flag("--no-segment", o->no_segment, "register against the whole scan (one part only)");
  app->add_option("--max-clusters", o->max_clusters,
                  "candidate parts tried: near the prior (else the largest) first")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app->add_option("--thresholds", o->thresholds,
                  "tuned thresholds (laserfit tune) instead of the defaults; "
                  "options given here still override them");
  app->add_option("--object", o->object,
                  "object name for the thresholds' per-object voxel (default: the "
                  "reference file's name without extension)");
  app->add_option(
         "--thin", o->thin,
         "thin parts (a thread: at most 0.5 mm thick, 5 diameters long) are detected "
         "along the prior's axis, not registered: auto (by the reference's shape) | on | off")
      ->check(CLI::IsMember(names_of<registration::ThinMode>()))
      ->capture_default_str();
  app->add_option("--thin-axis-sigma", o->thin_axis_sigma,
                  "thin parts: how good the prior's axis is (deg, 1 sigma; "
                  "0 = fit the axis freely)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option(
         "--weak-rotation", o->weak_rotation,
         "a rotation the task expects the scan not to pin (axis of the reference frame, e.g. a "
         "needle's spin about its shaft): ambiguous about it unless clearly observable")
      ->check(CLI::IsMember({"x", "y", "z"}));
  app->add_option("--weak-translation", o->weak_translation,
                  "likewise a translation (e.g. a plug's slide along "
                  "itself)")
      ->check(CLI::IsMember({"x", "y", "z"}));
  app->add_option("--max-sigma-um", o->max_sigma_um,
                  "trust: an ok whose origin moves by more than this (jackknife sigma, one region "
                  "of the scan "
                  "left out) is ambiguous, not pinned; your insertion tolerance (0 = no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--max-sigma-deg", o->max_sigma_deg, "likewise for the rotation (deg)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--fail-on", o->fail_on,
                  "exit 3 (results still printed) when a registration is failed, or with "
                  "'ambiguous' when it is ambiguous or failed: for scripts that must not act on it")
      ->check(CLI::IsMember({"ambiguous", "failed"}));
  add_jobs(*app, o->jobs);
  app->add_flag("--json", o->json, "machine-readable result on stdout");
  o->app = app;
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::cli
