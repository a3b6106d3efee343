// The paper's Algorithm 1 (lines cited below): filter and downsample the scan; RANSAC (FPFH) for
// a coarse pose; reject it when its orientation is farther than rho_rot from the prior q0 (d_phi,
// line 5); refine with ICP; keep the best fitness (the other methods: among the attempts that
// explain most of the scan, see pick_best); repeat until the fitness is below rho_ICP or the
// attempt budget runs out. Added: a second attempt must agree with the best one before stopping.
#include <Eigen/Eigenvalues>

#include "driver.hpp"
#include "laserfit/registration/preprocess.hpp"
#include "reference_cache.hpp"

namespace laserfit::registration {

Problem prepare_problem(const PointCloud& scan_in, const PointCloud& ref_in,
                        const RegistrationSettings& s, RegistrationResult& r) {
  Problem p{s};
  p.voxel = r.voxel_mm = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref_in);
  p.refine = refiner_fn(s.refine.method);
  p.matcher = {s.refine.max_correspondence_vox * p.voxel, s.pre.use_viewpoint};
  p.coarse = !(s.skip_coarse && s.prior);
  auto t = Clock::now();
  p.scan = prepare(scan_in, s.pre, p.voxel);
  r.timings_s["preprocess"] = since(t);

  t = Clock::now();
  const auto ref = prepared_reference(ref_in, s, p.voxel, p.coarse);
  p.ref = ref->ref, p.ref_tree = ref->tree, p.ref_c = ref->coarse, p.ref_f = ref->features;
  p.prepared = ref;
  r.timings_s["reference"] = since(t);

  t = Clock::now();
  p.scan_tree.reset(new Tree);
  p.scan_tree->setInputCloud(p.scan);
  if (p.coarse) {
    const double cvox = s.coarse.voxel_factor * p.voxel;
    p.scan_c = coarser(p.scan, cvox, s.pre, false);
    p.scan_f = fpfh(p.scan_c, s.coarse.feature_radius_vox * cvox);
  }
  r.timings_s["features"] = since(t);
  return p;
}

namespace {

// Line 4: a coarse pose, the prior (the robot's own belief) first when there is one.
bool hypothesis(const Problem& p, int a, Pose& T0) {
  const RegistrationSettings& s = p.s;
  T0 = s.prior.value_or(Pose::Identity());
  if (!p.coarse || (s.prior && a == 0)) return true;
  const double cvox = s.coarse.voxel_factor * p.voxel;
  const uint64_t seed = s.seed + 7919u * a;
  const bool found =
      s.coarse.method == CoarseMethod::Gated
          ? coarse_align_gated(p.ref_c, p.ref_f, p.scan_c, p.scan_f, s.coarse, cvox, seed, s.q0,
                               s.rho_rot_deg, T0)
          : coarse_align(p.ref_c, p.ref_f, p.scan_c, p.scan_f, s.coarse, cvox, seed, T0);
  return found && T0.matrix().allFinite();
}

double d_phi_deg(const Pose& T, const Eigen::Quaterniond& q0) {
  return rotation_angle(Eigen::Quaterniond(T.rotation()), q0) * 180 / M_PI;
}

// Line 6. PCL's least-squares ICP variants divide by a singular matrix when the data cannot fix
// all six directions (a cylinder seen from the side) and then abort inside PCL on NaN poses; the
// damped Ceres solve handles it, so degenerate data goes there.
RefineOutput refine_from(const Problem& p, const Pose& T0) {
  RefineFn use = p.refine;
  if (use != refine_ceres) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> es(
        plane_system(*p.scan, *p.ref_tree, T0, p.matcher).H);
    if (es.eigenvalues()[0] < 1e-6 * es.eigenvalues()[5]) use = refine_ceres;
  }
  return use(p.refine_input(T0));
}

// One round of lines 4-6: the refined candidate, or nullopt with the reason logged.
std::optional<Candidate> attempt(const Problem& p, int a, RegistrationResult& r, double& t_ransac,
                                 double& t_icp) {
  const RegistrationSettings& s = p.s;
  const std::string head = "attempt " + std::to_string(a + 1) + ": ";
  const bool from_prior = s.prior && a == 0;
  if (from_prior && p.coarse) r.log.push_back(head + "starting from the prior pose");
  auto t = Clock::now();
  Pose T0;
  const bool found = hypothesis(p, a, T0);
  t_ransac += since(t);
  if (!found) {
    r.log.push_back(head + "RANSAC found no hypothesis with inlier fraction " +
                    fmt(s.coarse.inlier_fraction));
    return std::nullopt;
  }
  if (s.q0 && !from_prior && d_phi_deg(T0, *s.q0) > s.rho_rot_deg) {  // line 5: unrealistic
    r.log.push_back(head + "rejected: d_phi(q, q0) = " + fmt(d_phi_deg(T0, *s.q0)) +
                    " deg > rho_rot");
    return std::nullopt;
  }
  if (p.coarse && !from_prior) r.log.push_back(head + "RANSAC pose " + fmt_t(T0));
  t = Clock::now();
  const RefineOutput out = refine_from(p, T0);
  t_icp += since(t);
  r.iterations += out.iterations;
  if (!out.T.matrix().allFinite()) {  // a degenerate solve (e.g. planar data): no pose
    r.log.push_back(head + "refinement diverged (non-finite pose)");
    return std::nullopt;
  }
  // The refined pose must stay inside the rho_rot cone too (not in the paper, which gates the
  // RANSAC pose only): refinement can slide a partly hidden part (a plug whose front is in the
  // socket) to a well-fitting pose 90 deg off.
  if (s.q0 && !s.policies.paper && d_phi_deg(out.T, *s.q0) > s.rho_rot_deg) {
    r.log.push_back(head + "rejected: refined to d_phi(q, q0) = " + fmt(d_phi_deg(out.T, *s.q0)) +
                    " deg > rho_rot");
    return std::nullopt;
  }
  const Candidate c{out.T, evaluate(*p.scan, *p.ref_tree, out.T, p.matcher)};
  r.log.push_back(head + "refined: fitness " + fmt(c.fit.fitness_mm2 / (p.voxel * p.voxel)) +
                  " voxel^2, rmse " + fmt(c.fit.rmse_mm * 1e3) + " um, overlap " +
                  fmt(c.fit.overlap) + ", " + fmt_t(out.T));
  return c;
}

}  // namespace

Attempts run_attempts(const Problem& p, RegistrationResult& r) {
  const double rho_icp = p.s.rho_icp_vox2 * p.voxel * p.voxel;
  Attempts a;
  double t_ransac = 0, t_icp = 0;
  for (int k = 0; k < p.s.max_attempts; ++k) {  // lines 2-8
    ++r.attempts;
    const auto c = attempt(p, k, r, t_ransac, t_icp);
    if (!c) continue;
    a.converged.push_back(*c);
    if (c->fit.fitness_mm2 < rho_icp) a.good.push_back(*c);  // line 7: below rho_ICP
    // Stop once two converged attempts agree (one when there is no coarse stage to repeat:
    // every attempt would repeat this one).
    if (!p.coarse) break;
    bool agreed = false;
    for (size_t i = 0; i + 1 < a.good.size() && !agreed; ++i)
      agreed = agree(a.good[i].T_scan_ref, a.good.back().T_scan_ref, *p.ref, p.s.trust);
    if (agreed) break;
  }
  r.timings_s["ransac"] = t_ransac;
  r.timings_s["refine"] = t_icp;
  return a;
}

namespace {
// The converged attempt to keep. Algorithm 1 keeps the lowest fitness (Policies::paper does),
// but fitness is averaged over the matched scan points only: a pose that lays the reference's
// plate on the scan's plate and matches nothing else fits those points more tightly than the
// right pose fits the whole part with its hole walls (o2ac panel: 2.7 um RMS over 21 % of the
// scan against 5.0 um over 96 %). So the other methods keep the lowest fitness among the
// attempts that explain nearly as much of the scan as any (fits_as_well's 98 %).
const Candidate* pick_best(const std::vector<Candidate>& all, bool paper) {
  double most = 0;
  for (const auto& c : all) most = std::max(most, c.fit.overlap);
  const Candidate* best = nullptr;
  for (const auto& c : all)
    if ((paper || c.fit.overlap >= 0.98 * most) &&
        (!best || c.fit.fitness_mm2 < best->fit.fitness_mm2))
      best = &c;
  return best;
}
}  // namespace

std::optional<Candidate> keep_best(const Problem& p, const Attempts& a, RegistrationResult& r) {
  const Candidate* kept = pick_best(a.converged, p.s.policies.paper);  // line 9
  if (!kept || !std::isfinite(kept->fit.fitness_mm2)) {
    r.status = Status::Failed;
    r.reason = "no RANSAC hypothesis survived (features do not match, or rho_rot rejected all)";
    return std::nullopt;
  }
  r.T_scan_ref = kept->T_scan_ref;
  assess(*p.scan, *p.ref_tree, p.matcher, p.s.trust, p.voxel, r);
  return *kept;
}

// Two poses agree when they place the reference's surface in the same place: the RMS of the
// displacement of its points along their normals is below the limit. Motions the surface cannot
// show (a needle spinning about its shaft, a peg sliding along its axis) do not count against
// agreement; they are what the Hessian test reports as ambiguous.
bool agree(const Pose& a, const Pose& b, const PclCloud& ref, const TrustSettings& t) {
  const Eigen::Matrix4f D = (a.matrix() - b.matrix()).cast<float>();
  const Eigen::Matrix3f Ra = a.rotation().cast<float>();
  const size_t step = std::max<size_t>(1, ref.size() / 2000);
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < ref.size(); i += step) {
    const auto& q = ref[i];
    const Eigen::Vector3f x = q.getVector3fMap(), nrm = Ra * q.getNormalVector3fMap();
    if (!x.allFinite() || !nrm.allFinite()) continue;
    const float d = nrm.dot(D.topLeftCorner<3, 3>() * x + D.topRightCorner<3, 1>());
    sum += double(d) * d, ++n;
  }
  return n > 0 && std::sqrt(sum / double(n)) <= t.restart_agreement_mm;
}

Candidate candidate(const RegistrationResult& r) {
  return {r.T_scan_ref, Fit{r.fitness_mm2, r.inlier_rmse_mm, r.overlap, 0}};
}

}  // namespace laserfit::registration
