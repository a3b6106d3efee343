// What laserfit adds to Algorithm 1 for its trust decision (Policies in settings.hpp). Each stage
// runs on the pose kept by line 9 and its assessment, and may change the pose (prefer_prior,
// slide) or the status (polish, reject_rivals, require_confirmation); none makes a failed pose ok.
#include "driver.hpp"
#include "slide.hpp"

namespace laserfit::registration {

namespace {
void adopt(const Problem& p, const Candidate& c, Candidate& best, RegistrationResult& r) {
  best = c;
  r.T_scan_ref = best.T_scan_ref;
  assess(*p.scan, *p.ref_tree, p.matcher, p.s.trust, p.voxel, r);
}
}  // namespace

// Where the data cannot decide (a shaft slides along itself), the prior can: of the converged
// attempts that fit as well as the best, keep the one nearest to it rather than the one with a
// marginally lower fitness several millimetres along the unobservable direction. Only those: an
// attempt that stopped on the plateau with its eye off the scan's eye (4.5x the fitness, 90 %
// overlap) is not an equal the prior may choose. The overlap band is 95 %, wider than
// fits_as_well's 98 %: a plug seen from the side fits a patch of its walls slid 8 mm along its
// axis at 100 % of a crop, the attempt from the prior at 97.5 % with the same RMS, and which of
// the two was kept depended on whether one RANSAC draw found a hypothesis.
void prefer_prior(const Problem& p, const Attempts& a, Candidate& best, RegistrationResult& r) {
  if (r.status != Status::Ambiguous || !p.s.prior) return;
  const Eigen::Vector3d prior = p.s.prior->translation();
  const auto equal = [&](const Fit& f) {
    return f.overlap >= 0.95 * best.fit.overlap && f.fitness_mm2 <= 1.5 * best.fit.fitness_mm2;
  };
  const Candidate* nearest = &best;
  for (const auto& c : a.good)
    if (equal(c.fit) && (c.T_scan_ref.translation() - prior).norm() <
                            (nearest->T_scan_ref.translation() - prior).norm())
      nearest = &c;
  if (nearest->T_scan_ref.matrix() == best.T_scan_ref.matrix()) return;
  r.log.push_back("ambiguous: kept the converged attempt nearest to the prior, " +
                  fmt_t(nearest->T_scan_ref));
  adopt(p, Candidate(*nearest), best, r);
}

// Ambiguous along a translation: where along it the attempts that fit as well converged (the
// plateau the slide search and a regrown crop must cover).
void measure_plateau(const Problem& p, const Attempts& a, const Candidate& best,
                     RegistrationResult& r) {
  if (r.status != Status::Ambiguous) return;
  const auto axis = flat_translation(r, p.s.trust);
  if (!axis) return;
  for (const auto& c : a.good)
    if (fits_as_well(c.fit, best.fit)) {
      const double along = axis->dot(c.T_scan_ref.translation() - best.T_scan_ref.translation());
      r.flat_from_mm = std::min(r.flat_from_mm, along);
      r.flat_to_mm = std::max(r.flat_to_mm, along);
    }
}

// slide.cpp: a pose flat along a translation the task did not declare weak is refined again from
// poses slid along it; a re-refinement the data pin is kept.
void slide(const Problem& p, Attempts& a, Candidate& best, RegistrationResult& r) {
  if (r.status != Status::Ambiguous) return;
  const auto t = Clock::now();
  if (const auto sl = slide_search(p.refine_input(best.T_scan_ref), p.matcher, p.s.trust, r)) {
    r.log.push_back("slide search: pinned by a refinement started " + fmt(sl->offset_mm) +
                    " mm along the flat translation: fitness " +
                    fmt(sl->result.fitness_mm2 / (p.voxel * p.voxel)) + " voxel^2, overlap " +
                    fmt(sl->result.overlap) + ", " + fmt_t(sl->result.T_scan_ref));
    r.iterations += sl->iterations;
    // The pinned re-refinements count as attempts for the checks below: as confirmations or as
    // rivals (two different pinned slides are a repeated structure, not a pose).
    for (const auto& x : sl->pinned) a.good.push_back(candidate(x));
    adopt(p, candidate(sl->result), best, r);
  }
  r.timings_s["slide"] = since(t);
}

// A pose is only trusted where the robust point-to-plane fit has its minimum: a PCL ICP that
// stopped on a plateau (sliding along a face) is caught here, not reported as ok.
void polish(const Problem& p, const Candidate& best, RegistrationResult& r) {
  if (r.status != Status::Ok || p.refine == refine_ceres) return;
  RefineSettings ps = p.s.refine;
  ps.robust_loss = RobustLoss::Huber;
  const RefineOutput pol = refine_ceres({p.ref, p.scan, p.scan_tree, p.ref_tree, best.T_scan_ref,
                                         p.voxel, ps, p.s.pre.use_viewpoint});
  const Pose& T = best.T_scan_ref;
  const double dt = (pol.T.translation() - T.translation()).norm();
  const double dr =
      Eigen::AngleAxisd(pol.T.rotation().transpose() * T.rotation()).angle() * 180 / M_PI;
  if (!pol.T.matrix().allFinite() || dt > p.s.trust.polish_mm || dr > p.s.trust.polish_deg) {
    r.status = Status::Failed;
    r.reason = "not at the minimum of the robust point-to-plane fit (polishing moves it " +
               fmt(dt * 1e3) + " um, " + fmt(dr) + " deg)";
  }
}

// Equally good refined poses (fits_as_well) that disagree: a symmetry or a repeated structure,
// not a pose.
void reject_rivals(const Problem& p, const Attempts& a, const Candidate& best,
                   RegistrationResult& r) {
  if (r.status != Status::Ok) return;
  for (const auto& c : a.good)
    if (!agree(c.T_scan_ref, best.T_scan_ref, *p.ref, p.s.trust) && fits_as_well(c.fit, best.fit)) {
      r.status = Status::Ambiguous;
      r.reason = "attempts converged to different poses with equal fit (symmetric part?)";
      return;
    }
}

// An ok found by RANSAC once may be luck: another converged attempt must agree with it.
void require_confirmation(const Problem& p, const Attempts& a, const Candidate& best,
                          RegistrationResult& r) {
  if (r.status != Status::Ok || !p.coarse || p.s.max_attempts < 2) return;
  size_t confirming = 0;  // converged attempts that agree with the best (itself included)
  for (const auto& c : a.good)
    confirming += agree(c.T_scan_ref, best.T_scan_ref, *p.ref, p.s.trust);
  if (confirming >= 2) return;
  r.status = Status::Failed;
  r.reason = "no second attempt confirmed the pose (" + std::to_string(a.good.size()) +
             " converged, none agreeing with the best)";
}

// Refined from the prior alone, nothing confirms the pose: a wrong local minimum (the panel slid
// along its plate onto another edge) fits most of the scan as well as the truth and leaves a
// minority of points far off. Residuals that look like noise (RMSE near their robust sigma) are
// the evidence an ok then rests on.
void require_consistent_residuals(const Problem& p, RegistrationResult& r) {
  const double k = p.s.trust.max_rmse_to_sigma;
  if (r.status != Status::Ok || p.coarse || k <= 0) return;
  if (r.inlier_rmse_mm <= std::max(k * r.residual_sigma_mm, p.s.trust.rmse_floor_mm)) return;
  r.status = Status::Failed;
  r.reason = "residuals are not noise: inlier RMSE " + fmt(r.inlier_rmse_mm * 1e3) + " um is " +
             fmt(r.inlier_rmse_mm / r.residual_sigma_mm) + "x their robust sigma " +
             fmt(r.residual_sigma_mm * 1e3) + " um (limit " + fmt(k) +
             "x; refined from the prior only, a wrong local minimum?)";
}

}  // namespace laserfit::registration
