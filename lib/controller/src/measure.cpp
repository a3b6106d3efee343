// A measurement: register the target and the part in one scan, with the robots' beliefs as priors.
#include <cmath>
#include <optional>
#include <sstream>

#include "laserfit/controller/controller.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::controller {
namespace {

Eigen::Vector3d viewpoint(const PointCloud& scan) {
  if (!scan.sensor_origin) throw Error("the scan has no sensor origin (laserfit.viewpoint header)");
  return *scan.sensor_origin;
}

registration::RegistrationResult register_one(const PointCloud& scan, const PointCloud& ref,
                                              const Pose& prior, const std::string& object,
                                              const std::string& weak_rotation,
                                              const std::string& weak_translation,
                                              const ControllerSettings& s, uint64_t seed,
                                              bool refine_only = false, int clusters = 2) {
  registration::RegistrationSettings rs;
  s.thresholds.apply(rs, object);
  // The cell's harmless DoFs are the ones the scan is expected not to pin.
  rs.trust.weak_rotation = registration::named_axis(weak_rotation);
  rs.trust.weak_translation = registration::named_axis(weak_translation);
  rs.prior = prior;
  rs.skip_coarse = refine_only;
  rs.prior_radius_mm = s.prior_radius_mm;
  // A thin part is looked for as far from its prior as a correction may reach: beyond, it would
  // be refused anyway; nearer, a part the arm's model put that far off would be missed.
  rs.thin.search_radius_mm = s.correction.max_translation_mm;
  rs.q0 = Eigen::Quaterniond(prior.rotation());
  rs.pre.use_viewpoint = true, rs.pre.viewpoint = viewpoint(scan);
  rs.seed = seed;
  rs.segment.max_clusters = clusters;  // the points near the prior, then the nearest clusters
  try {
    return registration::register_scan(scan, ref, rs);
  } catch (const Error& e) {
    registration::RegistrationResult r;
    r.status = registration::Status::Failed;
    r.reason = e.what();
    return r;
  }
}

}  // namespace

std::optional<Pose> turn_from_tracked(const registration::RegistrationResult& r,
                                      const Pose& tracked, const ControllerSettings& s) {
  const registration::Vector6d& d = r.weakest_direction;
  if (r.status != registration::Status::Ambiguous || r.not_pinned || r.unobservable != 1 ||
      d.head<3>().norm() <= d.tail<3>().norm())
    return std::nullopt;
  const Pose T = registration::along_weakest_to(r, tracked);
  const Pose D = tracked.inverse() * T;
  if (D.translation().norm() > s.tracked_target_mm ||
      Eigen::AngleAxisd(D.linear()).angle() > s.tracked_target_deg * M_PI / 180)
    return std::nullopt;
  return T;
}

// T with its rotation about its own axis `e` (object frame) replaced by the prior's: the
// registration left that spin unobservable (the needle about its shaft), so its value is
// arbitrary, and every pose derived from the target (the insertion axis, the part's prior, a
// goal 2 mm above the eye) would inherit it. Swing-twist split of the residual rotation.
Pose with_prior_spin(const Pose& T, const Pose& prior, const Eigen::Vector3d& e) {
  const Eigen::Quaterniond d(T.rotation().transpose() * prior.rotation());
  const double twist = 2 * std::atan2(d.vec().dot(e), d.w());
  Pose out = T;
  out.linear() = T.rotation() * Eigen::AngleAxisd(twist, e).toRotationMatrix();
  return out;
}

Measurement measure(const PointCloud& scan, const PointCloud& target_ref,
                    const PointCloud& part_ref, const Pose& target_prior, const Pose& part_prior,
                    const cell::CellSettings& cs, const ControllerSettings& s, uint64_t seed,
                    std::vector<std::string>& log, const std::optional<Pose>& tracked_target,
                    const std::optional<Pose>& tracked_part) {
  Measurement m;
  const auto &tname = cs.scene.objects[cs.target].name, &pname = cs.scene.objects[cs.part].name;
  std::string why;
  const std::string &tw_rot = cs.target_weak_rotation, &tw_trans = cs.target_weak_translation;
  auto check_target = [&] {
    m.T_scan_target = m.target.T_scan_ref;
    if (!acceptable(m.target, tw_rot, tw_trans, m.T_scan_target, &why)) {
      const auto T =
          tracked_target ? turn_from_tracked(m.target, *tracked_target, s) : std::nullopt;
      if (!T) return false;
      m.T_scan_target = *T, m.target_turn_tracked = true;
      log.push_back("  " + tname + " " + why + ": that turn is its last trusted measurement's");
      return true;
    }
    const std::string& w = cs.target_weak_rotation;
    if (m.target.status == registration::Status::Ambiguous && !w.empty()) {
      const Eigen::Vector3d e = *registration::named_axis(w);
      if (registration::weakest_is_rotation_about(m.target, m.T_scan_target.linear() * e)) {
        m.T_scan_target = with_prior_spin(m.T_scan_target, target_prior, e);
        m.target_prior_spin_axis = m.T_scan_target.linear() * e;
      }
    }
    return true;
  };
  // The target does not move and the sensing arm repeats its scan pose to ~0.1 mm: an earlier
  // measurement is a far better prior than the arm's model (mm off), and refining from it is
  // enough. It also keeps the whole target together where the part's shadow cuts it in two.
  bool ok = false;
  if (tracked_target) {
    m.target =
        register_one(scan, target_ref, *tracked_target, tname, tw_rot, tw_trans, s, seed, true);
    ok = check_target();
    if (!ok)
      log.push_back("refining " + tname + " from its last measurement: " + why +
                    "; full registration");
  }
  // With only the arm's model to go by, the target can lie ~30 mm from its prior (the sensing
  // arm's kinematic error), and nearer clusters (the part above it, the board) come first.
  if (!ok) {
    m.target = register_one(scan, target_ref, tracked_target ? *tracked_target : target_prior,
                            tname, tw_rot, tw_trans, s, seed, false, tracked_target ? 2 : 4);
    ok = check_target();
  }
  if (!ok) {
    m.reason = tname + " registration " + why;
    log.push_back("registered " + tname + ": " + registration::status_name(m.target.status) +
                  " -> rejected: " + m.reason);
    return m;
  }
  m.target_ok = true;
  // The part's prior relative to the measured target: both priors come from arm A's model and
  // share its absolute error (mm), the scan is in arm B's frame with its own; relative to the
  // target only the error between teaching and now is left.
  // Better still, the last measurement moved by the commands since (their error is ~0.1 of their
  // length, the model's is mm): a thread that returned nothing from a few profiles is seen in
  // pieces, and the piece nearest a prior mm off need not hold the tip (once 3 mm short).
  const Pose relative_prior =
      m.T_scan_target * (tracked_part ? *tracked_part : target_prior.inverse() * part_prior);
  m.part = register_one(scan, part_ref, relative_prior, pname, cs.part_weak_rotation,
                        cs.part_weak_translation, s, seed + 1);
  m.T_scan_part = m.part.T_scan_ref;
  if (!acceptable(m.part, cs.part_weak_rotation, cs.part_weak_translation, m.T_scan_part, &why)) {
    m.reason = pname + " registration " + why;
    // Where it was looked for: a prior far off is the usual reason a visible part is not found.
    const Eigen::Vector3d t = relative_prior.translation(), a = relative_prior.linear().col(2);
    std::ostringstream l;
    l.precision(4);
    l << "  " << pname << " prior (scan frame): origin " << t.transpose() << " mm, z axis "
      << a.transpose();
    log.push_back(l.str());
  } else {
    m.ok = true;
    // Not corrected along its own axis only when the scan could not fix it (a plug seen from
    // behind slides along itself). A thread's tip end is measured (to about one profile step):
    // it is corrected, or an IC2 approach's millimetres along the axis would stay (the tip
    // stopping above the eye, aligned but not inserted).
    m.part_axial_unknown =
        m.part.status == registration::Status::Ambiguous &&
        registration::weakest_is_translation_along(m.part, m.T_scan_part.linear().col(2));
  }
  std::ostringstream l;
  l << "registered " << tname << ": " << registration::status_name(m.target.status) << ", " << pname
    << ": " << registration::status_name(m.part.status)
    << (m.ok ? " -> accepted" : " -> rejected: " + m.reason);
  log.push_back(l.str());
  return m;
}

}  // namespace laserfit::controller
