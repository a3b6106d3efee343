// The paper's Algorithm 1: filter and downsample the scan; RANSAC (FPFH) for a coarse pose;
// reject it when its orientation is farther than rho_rot from the prior q0 (d_phi, line 5);
// refine with ICP; keep the best fitness (the other methods: among the attempts that explain
// most of the scan, see pick_best); repeat until the fitness is below rho_ICP or the attempt
// budget runs out. Added for automatic failure detection (the paper's future work): a
// second attempt must agree with the best one, and the final pose is assessed (trust.cpp).
#include <Eigen/Eigenvalues>
#include <chrono>

#include "laserfit/core/error.hpp"
#include "laserfit/registration/preprocess.hpp"
#include "slide.hpp"
#include "stages.hpp"

namespace laserfit::registration {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

size_t finite_points(const PointCloud& c) {
  size_t n = 0;
  for (const auto& p : c.points) n += p.allFinite();
  return n;
}

struct Candidate {
  Pose T;
  Fit fit;
};
Candidate candidate(const RegistrationResult& r) {  // an assessed pose: its fit is known
  return {r.T_scan_ref, Fit{r.fitness_mm2, r.inlier_rmse_mm, r.overlap, 0}};
}

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
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
    const auto& p = ref[i];
    const Eigen::Vector3f x = p.getVector3fMap(), nrm = Ra * p.getNormalVector3fMap();
    if (!x.allFinite() || !nrm.allFinite()) continue;
    const float d = nrm.dot(D.topLeftCorner<3, 3>() * x + D.topRightCorner<3, 1>());
    sum += double(d) * d, ++n;
  }
  return n > 0 && std::sqrt(sum / double(n)) <= t.restart_agreement_mm;
}

// The converged attempt to keep. Algorithm 1 keeps the lowest fitness (the `paper` method does),
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

const char* status_name(Status s) {
  switch (s) {
    case Status::Ok:
      return "ok";
    case Status::Ambiguous:
      return "ambiguous";
    case Status::Failed:
      return "failed";
  }
  return "?";
}

RegistrationResult register_cloud(const PointCloud& scan_in, const PointCloud& ref_in,
                                  const RegistrationSettings& s) {
  if (finite_points(scan_in) < 10) throw Error("scan has no usable points (empty or all NaN)");
  if (finite_points(ref_in) < 10) throw Error("reference cloud has no usable points");
  check_slide_settings(s.trust);
  if (uses_thin_detector(ref_in, s)) return detect_thin_part(scan_in, ref_in, s);
  const RefineFn refine = find_refiner(s.refine.method);
  RegistrationResult r;
  const double voxel = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref_in);
  r.voxel_mm = voxel;

  auto t = Clock::now();
  PreprocessSettings ref_pre = s.pre;
  ref_pre.use_viewpoint = false, ref_pre.outlier_std = 0;  // CAD samples have no outliers
  const PclCloud::Ptr scan = prepare(scan_in, s.pre, voxel);
  // The reference keeps its dense CAD samples and exact normals for refinement and assessment;
  // without normals, they are estimated.
  const PclCloud::Ptr ref = ref_in.has_normals() ? to_pcl(ref_in) : prepare(ref_in, ref_pre, voxel);
  r.timings_s["preprocess"] = since(t);

  t = Clock::now();
  Tree::Ptr tree(new Tree), ref_tree(new Tree);  // over the scan and the reference
  tree->setInputCloud(scan);
  ref_tree->setInputCloud(ref);
  Features::Ptr ref_f, scan_f;
  PclCloud::Ptr ref_c, scan_c;  // the coarser grid of the RANSAC stage
  const bool coarse = !(s.skip_coarse && s.prior);
  const double cvox = s.coarse.voxel_factor * voxel;
  if (s.coarse.method != "gated" && s.coarse.method != "pcl")
    throw Error("unknown coarse method '" + s.coarse.method + "' (gated, pcl)");
  const bool gated = s.coarse.method == "gated";
  if (coarse) {
    scan_c = coarser(scan, cvox, s.pre, false);
    ref_c = coarser(ref, cvox, ref_pre, true);
    ref_f = fpfh(ref_c, s.coarse.feature_radius_vox * cvox);
    scan_f = fpfh(scan_c, s.coarse.feature_radius_vox * cvox);
  }
  r.timings_s["features"] = since(t);

  const double gate = s.refine.max_correspondence_vox * voxel;
  const Matcher matcher{gate, s.pre.use_viewpoint};
  const double rho_icp = s.rho_icp_vox2 * voxel * voxel;
  std::vector<Candidate> good;       // refined poses with fitness below rho_ICP
  std::vector<Candidate> converged;  // every refined pose inside the rho_rot cone
  double t_ransac = 0, t_icp = 0;
  for (int a = 0; a < s.max_attempts; ++a) {
    ++r.attempts;
    Pose T0 = s.prior.value_or(Pose::Identity());
    t = Clock::now();
    const std::string head = "attempt " + std::to_string(a + 1) + ": ";
    const uint64_t seed = s.seed + 7919u * a;
    // A prior pose (the robot's own belief) is the first hypothesis; RANSAC supplies the rest.
    const bool from_prior = s.prior && a == 0;
    if (from_prior && coarse) r.log.push_back(head + "starting from the prior pose");
    const bool found = !coarse || from_prior ? true
                       : gated
                           ? coarse_align_gated(ref_c, ref_f, scan_c, scan_f, s.coarse, cvox, seed,
                                                s.q0, s.rho_rot_deg, T0)
                           : coarse_align(ref_c, ref_f, scan_c, scan_f, s.coarse, cvox, seed, T0);
    if (!found || !T0.matrix().allFinite()) {
      t_ransac += since(t);
      r.log.push_back(head + "RANSAC found no hypothesis with inlier fraction " +
                      fmt(s.coarse.inlier_fraction));
      continue;
    }
    t_ransac += since(t);
    if (s.q0 && !from_prior) {
      const double d_phi = rotation_angle(Eigen::Quaterniond(T0.rotation()), *s.q0) * 180 / M_PI;
      if (d_phi > s.rho_rot_deg) {  // Algorithm 1, line 5: unrealistic orientation
        r.log.push_back(head + "rejected: d_phi(q, q0) = " + fmt(d_phi) + " deg > rho_rot");
        continue;
      }
    }
    if (coarse && !from_prior)
      r.log.push_back(head + "RANSAC pose t = [" + fmt(T0.translation().x()) + ", " +
                      fmt(T0.translation().y()) + ", " + fmt(T0.translation().z()) + "]");
    t = Clock::now();
    // PCL's least-squares ICP variants divide by a singular matrix when the data cannot fix all
    // six directions (a cylinder seen from the side) and then abort inside PCL on NaN poses; the
    // damped Ceres solve handles it, so degenerate data goes there.
    RefineFn use = refine;
    if (refine != refine_ceres) {
      const Eigen::SelfAdjointEigenSolver<Matrix6d> es(
          plane_system(*scan, *ref_tree, T0, matcher).H);
      if (es.eigenvalues()[0] < 1e-6 * es.eigenvalues()[5]) use = refine_ceres;
    }
    const RefineOutput out =
        use({ref, scan, tree, ref_tree, T0, voxel, s.refine, s.pre.use_viewpoint});
    t_icp += since(t);
    r.iterations += out.iterations;
    if (!out.T.matrix().allFinite()) {  // a degenerate solve (e.g. planar data): no pose
      r.log.push_back(head + "refinement diverged (non-finite pose)");
      continue;
    }
    // The refined pose must stay inside the rho_rot cone too (not in the paper, which gates the
    // RANSAC pose only): refinement can slide a partly hidden part (a plug whose front is in the
    // socket) to a well-fitting pose 90 deg off. The paper method keeps the paper's behaviour.
    if (s.q0 && s.refine.method != "paper") {
      const double d_phi = rotation_angle(Eigen::Quaterniond(out.T.rotation()), *s.q0) * 180 / M_PI;
      if (d_phi > s.rho_rot_deg) {
        r.log.push_back(head + "rejected: refined to d_phi(q, q0) = " + fmt(d_phi) +
                        " deg > rho_rot");
        continue;
      }
    }
    const Candidate c{out.T, evaluate(*scan, *ref_tree, out.T, matcher)};
    r.log.push_back(head + "refined: fitness " + fmt(c.fit.fitness_mm2 / (voxel * voxel)) +
                    " voxel^2, rmse " + fmt(c.fit.rmse_mm * 1e3) + " um, overlap " +
                    fmt(c.fit.overlap) + ", t = [" + fmt(out.T.translation().x()) + ", " +
                    fmt(out.T.translation().y()) + ", " + fmt(out.T.translation().z()) + "]");
    converged.push_back(c);
    if (c.fit.fitness_mm2 < rho_icp) good.push_back(c);
    // Stop once two converged attempts agree (one when there is no coarse stage to repeat).
    if (!coarse) break;  // without a coarse stage every attempt would repeat this one
    bool agreed = false;
    for (size_t i = 0; i + 1 < good.size() && !agreed; ++i)
      agreed = agree(good[i].T, good.back().T, *ref, s.trust);
    if (agreed) break;
  }
  r.timings_s["ransac"] = t_ransac;
  r.timings_s["refine"] = t_icp;

  t = Clock::now();
  const Candidate* kept = pick_best(converged, s.refine.method == "paper");
  if (!kept || !std::isfinite(kept->fit.fitness_mm2)) {
    r.status = Status::Failed;
    r.reason = "no RANSAC hypothesis survived (features do not match, or rho_rot rejected all)";
    r.timings_s["assess"] = since(t);
    return r;
  }
  Candidate best = *kept;
  r.T_scan_ref = best.T;
  assess(*scan, *ref_tree, matcher, s.trust, voxel, r);
  if (r.status == Status::Ambiguous && s.prior) {
    // Where the data cannot decide (a shaft slides along itself), the prior can: of the converged
    // attempts that fit as well as the best, keep the one nearest to it rather than the one with a
    // marginally lower fitness several millimetres along the unobservable direction. Only those:
    // an attempt that stopped on the plateau with its eye off the scan's eye (4.5x the fitness,
    // 90 % overlap) is not an equal the prior may choose (trial 328's scan, the prior 3 mm behind).
    const Candidate* nearest = &best;
    for (const auto& c : good)
      if (fits_as_well(c.fit, best.fit) &&
          (c.T.translation() - s.prior->translation()).norm() <
              (nearest->T.translation() - s.prior->translation()).norm())
        nearest = &c;
    if (nearest->T.matrix() != best.T.matrix()) {
      r.log.push_back("ambiguous: kept the converged attempt nearest to the prior, t = [" +
                      fmt(nearest->T.translation().x()) + ", " + fmt(nearest->T.translation().y()) +
                      ", " + fmt(nearest->T.translation().z()) + "]");
      best = *nearest;
      r.T_scan_ref = best.T;
      assess(*scan, *ref_tree, matcher, s.trust, voxel, r);
    }
  }
  if (r.status == Status::Ambiguous) {
    t = Clock::now();
    if (const auto axis = flat_translation(r, s.trust))
      for (const auto& c : good)
        if (fits_as_well(c.fit, best.fit)) {
          const double along = axis->dot(c.T.translation() - best.T.translation());
          r.flat_from_mm = std::min(r.flat_from_mm, along),
          r.flat_to_mm = std::max(r.flat_to_mm, along);
        }
    const RefineInput in{ref, scan, tree, ref_tree, best.T, voxel, s.refine, s.pre.use_viewpoint};
    if (const auto sl = slide_search(in, matcher, s.trust, r)) {
      const Pose& T = sl->result.T_scan_ref;
      r.log.push_back("slide search: pinned by a refinement started " + fmt(sl->offset_mm) +
                      " mm along the flat translation: fitness " +
                      fmt(sl->result.fitness_mm2 / (voxel * voxel)) + " voxel^2, overlap " +
                      fmt(sl->result.overlap) + ", t = [" + fmt(T.translation().x()) + ", " +
                      fmt(T.translation().y()) + ", " + fmt(T.translation().z()) + "]");
      r.iterations += sl->iterations;
      best = candidate(sl->result);
      // Converged attempts too: the checks below count them as confirmations or as rivals (two
      // different pinned slides are a repeated structure, not a pose).
      for (const auto& p : sl->pinned) good.push_back(candidate(p));
      r.T_scan_ref = best.T;
      assess(*scan, *ref_tree, matcher, s.trust, voxel, r);
    }
    r.timings_s["slide"] = since(t);
  }
  if (r.status == Status::Ok && refine != refine_ceres) {
    // A pose is only trusted where the robust point-to-plane fit has its minimum: a PCL ICP
    // that stopped on a plateau (sliding along a face) is caught here, not reported as ok.
    RefineSettings ps = s.refine;
    ps.robust_loss = "huber";
    const RefineOutput pol =
        refine_ceres({ref, scan, tree, ref_tree, best.T, voxel, ps, s.pre.use_viewpoint});
    const double dt = (pol.T.translation() - best.T.translation()).norm();
    const double dr =
        Eigen::AngleAxisd(pol.T.rotation().transpose() * best.T.rotation()).angle() * 180 / M_PI;
    if (!pol.T.matrix().allFinite() || dt > s.trust.polish_mm || dr > s.trust.polish_deg) {
      r.status = Status::Failed;
      r.reason = "not at the minimum of the robust point-to-plane fit (polishing moves it " +
                 fmt(dt * 1e3) + " um, " + fmt(dr) + " deg)";
    }
  }
  if (r.status == Status::Ok) {
    // Equally good refined poses (fits_as_well) that disagree: a symmetry or a repeated
    // structure, not a pose.
    for (const auto& c : good)
      if (!agree(c.T, best.T, *ref, s.trust) && fits_as_well(c.fit, best.fit)) {
        r.status = Status::Ambiguous;
        r.reason = "attempts converged to different poses with equal fit (symmetric part?)";
        break;
      }
    size_t confirming = 0;  // converged attempts that agree with the best (itself included)
    for (const auto& c : good) confirming += agree(c.T, best.T, *ref, s.trust);
    if (r.status == Status::Ok && coarse && confirming < 2 && s.max_attempts >= 2) {
      r.status = Status::Failed;
      r.reason = "no second attempt confirmed the pose (" + std::to_string(good.size()) +
                 " converged, none agreeing with the best)";
    }
  }
  check_pinned(s.trust, r);
  r.timings_s["assess"] = since(t);
  return r;
}

PointCloud crop_near(const PointCloud& scan, const PointCloud& ref, const Pose& T_scan_ref,
                     double radius, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  // Copies slid at most one radius apart: their balls overlap, so the crop is one swept tube.
  const int n = radius > 0 ? int(std::ceil((to - from).norm() / radius - 1e-9)) : 0;
  std::vector<Eigen::Vector3f> placed;
  Eigen::AlignedBox3f box;
  for (int k = 0; k <= n; ++k) {
    const Pose T =
        Eigen::Translation3d(from + (n ? double(k) / n : 0.0) * (to - from)) * T_scan_ref;
    for (const auto& p : ref.points) {
      if (!p.allFinite()) continue;
      placed.push_back((T * p.cast<double>()).cast<float>());
      box.extend(placed.back());
    }
  }
  PointCloud out;
  out.metadata = scan.metadata;
  if (placed.empty()) return out;
  box.min().array() -= float(radius), box.max().array() += float(radius);
  std::vector<size_t> at;
  std::vector<Eigen::Vector3f> queries;
  for (size_t i = 0; i < scan.points.size(); ++i)
    if (scan.points[i].allFinite() && box.contains(scan.points[i]))
      queries.push_back(scan.points[i]), at.push_back(i);
  // Radius-bounded and batched: most scan points are far from the part, and an unbounded nearest
  // search from them descends much of the tree (the o2ac panel's 1.5 M points against a crop
  // swept 20 mm: an 18-minute registration, taskboard trial 40, then 10 s); one PCL query per
  // point opened an OpenMP region in FLANN per point (0.7 s of a 1 M-point scan's 1.4 s).
  const std::vector<char> near = within_radius(placed, queries, radius);
  const bool labels = !scan.labels.empty();
  for (size_t k = 0; k < at.size(); ++k) {
    if (!near[k]) continue;
    out.points.push_back(scan.points[at[k]]);
    if (labels) out.labels.push_back(scan.labels[at[k]]);
  }
  out.width = int(out.points.size());
  out.height = 1;
  return out;
}

RegistrationResult register_segmented(const PointCloud& scan_in, const PointCloud& ref,
                                      const RegistrationSettings& s, int max_clusters,
                                      int* cluster) {
  if (uses_thin_detector(ref, s)) return detect_thin_part(scan_in, ref, s);  // segments itself
  check_slide_settings(s.trust);
  const auto t0 = std::chrono::steady_clock::now();
  PointCloud scan = scan_in;
  remove_mixed_pixels(scan);
  const double voxel = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref);
  // Parts further apart than 3 voxels are separate; a part needs at least 20 voxels (a 0.15 mm
  // thread tip seen over a millimetre is a few dozen).
  auto parts = segment_clusters(scan, voxel, 3 * voxel, 20);
  // With a prior, the scan points near the reference placed at the prior form one more candidate:
  // a sparse part (a thin thread seen along its length) falls apart into clusters too small to
  // keep, but it is where the arm says it is.
  if (s.prior) {
    PointCloud near = crop_near(scan, ref, *s.prior, s.prior_radius_mm);
    if (near.points.size() >= 10) parts.insert(parts.begin(), std::move(near));
  }
  if (parts.empty()) throw Error("no part of the scan is large enough to register");
  // Try the parts nearest the prior first (where the arm believes the object is), else the
  // largest first; stop at the first one that registers ok.
  std::vector<int> order(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) order[i] = int(i);
  if (s.prior) {
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    size_t n = 0;
    for (const auto& p : ref.points)
      if (p.allFinite()) c += p, ++n;
    const Eigen::Vector3f at =
        (*s.prior * (c / float(std::max<size_t>(n, 1))).cast<double>()).cast<float>();
    std::vector<float> dist(parts.size(), std::numeric_limits<float>::infinity());
    for (size_t i = 0; i < parts.size(); ++i)
      for (const auto& p : parts[i].points) dist[i] = std::min(dist[i], (p - at).squaredNorm());
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist[a] < dist[b]; });
  }
  const double t_segment =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // A part's slide search (slide.cpp) is left to the regrown registration below: it sees every
  // piece of the part, the cluster may have lost what pins it.
  RegistrationSettings each = s;
  each.trust.slide_range_mm = 0;
  RegistrationResult best;
  int best_i = -1;
  auto rank = [](const RegistrationResult& r) {
    return r.status == Status::Ok ? 0 : r.status == Status::Ambiguous ? 1 : 2;
  };
  for (int k = 0; k < int(order.size()) && k < max_clusters; ++k) {
    const int i = order[k];
    if (parts[i].points.size() < 10) continue;
    RegistrationResult r;
    try {
      r = register_cloud(parts[i], ref, each);
    } catch (const Error& e) {  // a candidate too small to register is a failed candidate
      r.status = Status::Failed;
      r.reason = std::string("part ") + std::to_string(i) + ": " + e.what();
    }
    // Equal ranks: with a prior the earlier (nearer) part wins — a thread registered onto the
    // needle's shaft fits as well as onto the thread; without one, the lower fitness.
    if (best_i < 0 || rank(r) < rank(best) ||
        (rank(r) == rank(best) && !s.prior && r.fitness_mm2 < best.fitness_mm2))
      best = std::move(r), best_i = i;
    if (best.status == Status::Ok) break;
  }
  // A part cut in two by another's shadow (the thread across the needle's eye) leaves clusters
  // that miss what pins it (the needle's end beyond the shadow): their pose slides along the
  // shaft and comes back ambiguous. Near the pose found, every piece of the part is within reach:
  // refine once more on all scan points near the reference placed there.
  if (best.status != Status::Failed && best.unobservable > 0) {
    // A pose flat along a translation may be anywhere on the plateau its equally good attempts
    // spread over, and up to the slide range beyond: the crop and the slide search reach that
    // far along it, or they miss what pins the part (the needle's head beyond its eye: 1.2 mm
    // away with the prior 3 mm off; 6.3 mm with attempts spread over the shaft, trial 167).
    RegistrationSettings g = s;
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
    const auto flat = flat_translation(best, s.trust);
    if (flat && s.trust.slide_range_mm > 0) {
      const double range = s.trust.slide_range_mm;
      from = (best.flat_from_mm - range) * *flat, to = (best.flat_to_mm + range) * *flat;
      g.trust.slide_range_mm = std::min(range + std::max(-best.flat_from_mm, best.flat_to_mm),
                                        max_slide_steps * s.trust.slide_step_mm);
    }
    PointCloud grown = crop_near(scan, ref, best.T_scan_ref, s.prior_radius_mm, from, to);
    if (grown.points.size() >= 10) {
      // Flat along one translation (a shaft), the part slides on a line the crop and the slide
      // search cover, so refining from the pose found is enough. Flat in more (a piece of plate:
      // two translations and a spin) it may sit anywhere on that plane and the pose found is a
      // guess: the grown crop is registered afresh (that pose first, then RANSAC) with the rival
      // and confirmation checks of any registration. Refined from the guess, the o2ac panel
      // (taskboard trial 53) came back ok 15.6 mm off, explaining half the crop.
      g.prior = best.T_scan_ref, g.skip_coarse = flat && best.flat == 1;
      try {
        RegistrationResult r = register_cloud(grown, ref, g);
        const bool better =
            rank(r) < rank(best) || (rank(r) == rank(best) && r.unobservable < best.unobservable);
        best.log.push_back(std::string("regrown around the pose found (flat in ") +
                           std::to_string(best.flat) +
                           (g.skip_coarse ? ", refined): " : ", registered afresh): ") +
                           status_name(r.status) + (r.reason.empty() ? "" : " (" + r.reason + ")") +
                           ", " + std::to_string(r.unobservable) + " unobservable direction(s)" +
                           (better ? " -> kept" : " -> not better"));
        if (better) {
          r.log.insert(r.log.begin(), best.log.begin(), best.log.end());
          for (const auto& [k, v] : best.timings_s) r.timings_s[k] += v;
          best = std::move(r), best_i = int(parts.size());
        }
      } catch (const Error& e) {
        best.log.push_back(std::string("regrown around the pose found: ") + e.what());
      }
    }
  }
  if (cluster) *cluster = best_i;
  best.timings_s["segment"] = t_segment;
  best.log.push_back("segmentation: " + std::to_string(parts.size()) +
                     " candidate parts, registered part " + std::to_string(best_i));
  return best;
}

}  // namespace laserfit::registration
