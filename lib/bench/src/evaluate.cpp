// One trial's registrations: every (target, method), scored against the ground truth modulo the
// target's symmetries.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "laserfit/bench/memory.hpp"
#include "laserfit/bench/runner.hpp"
#include "laserfit/bench/trial.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/scan/reference.hpp"

namespace laserfit::bench {

registration::RegistrationSettings method_settings(const Benchmark& b, registration::Method method,
                                                   const Target& target,
                                                   const registration::Thresholds* thresholds) {
  registration::RegistrationSettings s;
  // The defaults (50 um, 0.5 deg) are the campaign's tolerance; a benchmark scored at 5 um must
  // not call a pose ok whose origin a left-out region of the scan moves by 20.
  s.trust.max_sigma_mm = b.t_tol_mm, s.trust.max_sigma_deg = b.r_tol_deg;
  if (thresholds)
    thresholds->apply(s, target.object, target.voxel_mm);
  else
    s.pre.voxel_mm = target.voxel_mm;
  s.trust.weak_rotation = target.weak_rotation, s.trust.weak_translation = target.weak_translation;
  registration::apply_method(s, method);
  return s;
}

namespace {

// Normals face the sensor where the scan says where it was (a recorded scan may not).
void use_viewpoint(registration::RegistrationSettings& s, const PointCloud& scan) {
  s.pre.use_viewpoint = bool(scan.sensor_origin);
  if (scan.sensor_origin) s.pre.viewpoint = *scan.sensor_origin;
}

// The scan near the registered reference (label 0) and the reference at the estimate (label 1),
// for the report's overlays (the paper's Fig. 5 and 7).
void write_overlay(const std::string& path, const PointCloud& scan, const PointCloud& ref,
                   const Pose& T) {
  PointCloud o = registration::crop_near(scan, ref, T, 1.0);
  o.labels.assign(o.points.size(), 0);
  for (const auto& p : ref.points) {
    o.points.push_back((T.cast<float>() * p).eval());
    o.labels.push_back(1);
  }
  o.normals.clear();
  o.width = int(o.points.size()), o.height = 1;
  o.sensor_origin = scan.sensor_origin;
  o.metadata = {{"overlay", "label 0 scan, 1 registered reference"}};
  io::write_cloud(path, o);
}

// Does an `ambiguous` result name one of the target's declared weak DoFs? Its weakest Hessian
// direction must lie within 10 deg of that axis (scan frame), and it may have no more
// unobservable directions than the target declares.
struct WeakNamed {
  bool rotation = false, translation = false;
};
WeakNamed names_weak(const registration::RegistrationResult& r, const Target& tg,
                     const Pose& truth) {
  const bool continuous = tg.symmetry.kind == metrics::Symmetry::Kind::Continuous;
  const int declared = bool(tg.weak_rotation) + bool(tg.weak_translation) + continuous;
  if (r.status != registration::Status::Ambiguous || r.unobservable > declared) return {};
  auto rot = [&](const std::optional<Eigen::Vector3d>& a) {
    return a && registration::weakest_is_rotation_about(r, truth.rotation() * *a);
  };
  const bool named = rot(tg.weak_rotation) || (continuous && rot(tg.symmetry.axis)) ||
                     (tg.weak_translation && registration::weakest_is_translation_along(
                                                 r, truth.rotation() * *tg.weak_translation));
  if (!named) return {};
  return {bool(tg.weak_rotation), bool(tg.weak_translation)};
}

// How much of target k the scan holds (its labelled points; -1: a scan without labels): a
// perturbation can move a 150 um thread out of the sweep or the measuring range, and a
// registration that then fails has not missed anything. Of a thin part only its side counts:
// seen end-on, a thread shows its modelled segment's cut end (a disc a real thread does not
// have) and a few side points, from which nothing can find it (the needle suite's thread, 18 of
// 60 trials at <= 13 side points).
long visible_points(const TrialInput& in, const PreparedScene& p, size_t k) {
  if (in.scan.labels.empty() || p.object[k] < 0) return -1;
  const bool thin = registration::thin_profile(p.reference[k], registration::ThinSettings{}).thin;
  double z0 = INFINITY, z1 = -INFINITY;  // the model's end planes (part frame)
  for (const auto& v : p.model[k])
    z0 = std::min(z0, double(v.z())), z1 = std::max(z1, double(v.z()));
  const double margin = 0.02;  // mm: off an end face by more than the depth noise
  const Pose object_scan = in.truth[k].inverse();
  long n = 0;
  for (size_t i = 0; i < in.scan.labels.size(); ++i) {
    if (in.scan.labels[i] != p.object[k] || !in.scan.points[i].allFinite()) continue;
    const double z = (object_scan * in.scan.points[i].cast<double>()).z();
    n += !thin || (z > z0 + margin && z < z1 - margin);
  }
  return n;
}

// A registration result scored against the truth by the benchmark's rule.
struct Score {
  bool success = false, false_accept = false, weak_named = false;
  metrics::PoseError e, full;  // modulo the symmetries and named weak DoFs / the symmetry only
};
Score score(const Benchmark& b, const PreparedScene& p, size_t k, const Target& tg,
            const Pose& truth, const registration::RegistrationResult& res) {
  Score sc;
  const WeakNamed weak = names_weak(res, tg, truth);
  sc.weak_named = weak.rotation || weak.translation;
  metrics::Symmetry sym = tg.symmetry;
  if (weak.rotation) sym.kind = metrics::Symmetry::Kind::Continuous, sym.axis = *tg.weak_rotation;
  Pose est = res.T_scan_ref;  // without the unobservable translation
  if (weak.translation) {
    const Eigen::Vector3d a = truth.rotation() * *tg.weak_translation;
    est.translation() -= a * a.dot(est.translation() - truth.translation());
  }
  sc.e = metrics::pose_error(est, truth, sym, p.model[k]);
  sc.full = metrics::pose_error(res.T_scan_ref, truth, tg.symmetry);
  const bool within = sc.e.t_mm <= b.t_tol_mm && sc.e.r_deg <= b.r_tol_deg;
  if (tg.expect_failure) {  // a wrong object must not be accepted
    sc.success = res.status != registration::Status::Ok;
    sc.false_accept = !sc.success;
  } else {
    const bool sym_ok = res.status == registration::Status::Ambiguous &&
                        (tg.symmetry.kind == metrics::Symmetry::Kind::Continuous || sc.weak_named);
    sc.success = within && (res.status == registration::Status::Ok || sym_ok);
    sc.false_accept = res.status == registration::Status::Ok && !within;
  }
  return sc;
}

}  // namespace

// Can this scan determine the target's pose at all? The default method refined from the true pose
// on the scan points near it: when even that is no success by the benchmark's rule (a view of the
// o2ac panel's plate alone leaves two translations and a spin flat; a few hole walls only weakly
// hold the slide along its flange), no method can answer `ok` and be right, and `ambiguous` is
// the honest answer. Reported apart from the success rate, which still counts such trials as
// misses.
// The view reference is sampled afresh from the part at its true pose. The benchmark's reference
// shows the nominally placed part: on a part turned by up to 20 deg it has walls the scan lacks
// and lacks walls the scan has, and refined against it from the truth, that mismatch held a
// socket's slide along its own axis which the scan itself does not hold (6 of registration.yaml's
// 200 receptacle trials).
AtTruth at_truth(const Benchmark& b, const PreparedScene& p, const Trial& t, const TrialInput& in,
                 size_t k, const registration::Thresholds* thresholds) {
  const Target& tg = b.scenes[t.scene].targets[k];
  registration::RegistrationSettings s =
      method_settings(b, registration::Method::Ceres, tg, thresholds);
  // Without a prior no gate: the scan must tell the truth from every near-symmetric twin.
  if (in.has_prior) s.q0 = Eigen::Quaterniond(in.truth[k].rotation());
  use_viewpoint(s, in.scan), s.seed = t.seed;
  s.prior = in.truth[k], s.skip_coarse = true;
  // Whether the scan determines the pose, not whether a refinement found it: refined from the
  // truth there is no wrong local minimum for the residual check to catch.
  s.policies.consistent = false;
  AtTruth a;
  try {
    // Bench scans are in the base frame, so T_scan_object is the T_base_object to view it at.
    const PointCloud ref = tg.reference == ReferenceSource::View
                               ? scan::view_reference(p.reference_mesh[k], in.truth[k],
                                                      p.scene.settings, tg.reference_points, b.seed)
                               : p.reference[k];
    const PointCloud near = registration::crop_near(in.scan, ref, in.truth[k], s.prior_radius_mm);
    const auto res = registration::register_cloud(near, ref, s);
    a.determinable = score(b, p, k, tg, in.truth[k], res).success;
    a.status = registration::status_name(res.status), a.reason = res.reason;
  } catch (const Error& e) {  // too little of it in the scan
    a.status = "failed", a.reason = std::string("error: ") + e.what();
  }
  return a;
}

// Target k registered by method m as the trial's settings say; an unusable scan (an Error) is
// a failed registration of the trial.
registration::RegistrationResult register_target(const Benchmark& b, const PreparedScene& p,
                                                 const Trial& t, const TrialInput& in, size_t k,
                                                 registration::Method m, const TrialOptions& o) {
  const Target& tg = b.scenes[t.scene].targets[k];
  const bool paper = m == registration::Method::Paper;
  auto rs = method_settings(b, m, tg, o.thresholds);
  if (in.has_prior) {  // else (prior: none, no scene_prior.json) it registers globally
    rs.q0 = Eigen::Quaterniond(in.prior[k].rotation());
    if (!paper) rs.prior = in.prior[k];
  }
  use_viewpoint(rs, in.scan);
  rs.seed = t.seed;
  // Two candidate parts: the points near the prior-placed reference, then the nearest cluster
  // (the CLI default tries four).
  rs.segment.max_clusters = 2;
  registration::ViewSampler view;
  if (tg.resample_view && !paper)
    view = [&](const Pose& T_scan_ref) {  // bench scans are in the base frame
      return scan::view_reference(p.reference_mesh[k], T_scan_ref, p.scene.settings,
                                  tg.reference_points, b.seed);
    };
  try {
    return registration::register_scan(in.scan, p.reference[k], rs, view);
  } catch (const Error& e) {
    registration::RegistrationResult res;
    res.status = registration::Status::Failed;
    res.reason = std::string("error: ") + e.what();
    return res;
  }
}

std::vector<io::Json> run_trial(const Benchmark& b, const PreparedScene& p, const Trial& t,
                                const TrialInput& in, const TrialOptions& o) {
  std::vector<io::Json> out;
  const auto& sc = b.scenes[t.scene];
  io::Json cond = io::Json::object();
  for (const auto& name : axis_names()) cond[name] = axis(t.conditions, name);
  for (size_t k = 0; k < sc.targets.size(); ++k) {
    const Target& tg = sc.targets[k];
    const long visible = visible_points(in, p, k);
    AtTruth truth_check;
    if (!tg.expect_failure) truth_check = at_truth(b, p, t, in, k, o.thresholds);
    for (const auto m : o.methods) {
      const MemoryProbe mem;
      const auto t0 = std::chrono::steady_clock::now();
      const auto res = register_target(b, p, t, in, k, m, o);
      const double time_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const Score grade = score(b, p, k, tg, in.truth[k], res);
      const auto &e = grade.e, &full = grade.full;
      io::Json timing = {
          {"time_s", time_s}, {"peak_rss_mb", mem.peak_mb()}, {"memory_scope", mem.scope()}};
      for (const auto& [stage, s] : res.timings_s) timing["stages_s"][stage] = s;
      out.push_back(
          {{"benchmark", b.name},
           {"scene", sc.name},
           {"object", tg.object},
           {"method", name_of(m)},
           {"trial", t.index},
           {"cell", t.cell},
           {"repetition", t.repetition},
           {"seed", t.seed},
           {"conditions", cond},
           {"expect", tg.expect_failure ? "failure" : "pose"},
           {"status", registration::status_name(res.status)},
           {"reason", res.reason},
           {"weak_axis_named", grade.weak_named},
           {"success", grade.success},
           {"false_accept", grade.false_accept},
           {"t_err_um", e.t_mm * 1e3},
           {"r_err_deg", e.r_deg},
           {"t_err_full_um", full.t_mm * 1e3},
           {"r_err_full_deg", full.r_deg},
           {"mssd_um", e.mssd_mm * 1e3},
           {"fitness_mm2", res.fitness_mm2},
           {"rmse_um", res.inlier_rmse_mm * 1e3},
           {"residual_sigma_um", res.residual_sigma_mm * 1e3},
           {"overlap", res.overlap},
           {"attempts", res.attempts},
           {"voxel_mm", res.voxel_mm},
           {"hessian_ratio", res.hessian_eigenvalues[5] > 0
                                 ? res.hessian_eigenvalues[0] / res.hessian_eigenvalues[5]
                                 : 0.0},
           {"sigma_origin_um", res.sigma_origin_mm * 1e3},
           {"sigma_rotation_deg", res.sigma_rotation_deg},
           {"scan_points", in.scan_points},
           {"visible_points", visible},
           {"determinable", tg.expect_failure || (truth_check.determinable && in_view(visible))},
           {"at_truth", {{"status", truth_check.status}, {"reason", truth_check.reason}}},
           {"T_scan_ref", io::pose_to_json(res.T_scan_ref).at("matrix")},
           {"timing", timing}});
      if (t.image >= 0) out.back()["image"] = t.image;  // a recorded scan's id
      if (!o.overlay_dir.empty() && t.cell == 0 && t.repetition == 0)
        write_overlay(o.overlay_dir + "/" + sc.name + "_" + tg.object + "_" + name_of(m) + ".pcd",
                      in.scan, p.reference[k], res.T_scan_ref);
    }
  }
  return out;
}

}  // namespace laserfit::bench
