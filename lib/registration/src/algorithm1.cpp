// The paper's Algorithm 1: filter and downsample the scan; RANSAC (FPFH) for a coarse pose;
// reject it when its orientation is farther than rho_rot from the prior q0 (d_phi, line 5);
// refine with ICP; keep the best fitness; repeat until the fitness is below rho_ICP or the
// attempt budget runs out. Added for automatic failure detection (the paper's future work): a
// second attempt must agree with the best one, and the final pose is assessed (trust.cpp).
#include <Eigen/Eigenvalues>
#include <chrono>

#include "laserfit/core/error.hpp"
#include "laserfit/registration/preprocess.hpp"
#include "stages.hpp"

namespace laserfit::registration {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

size_t finite_points(const PointCloud& c) {
  size_t n = 0;
  for (const auto& p : c.points) n += p.allFinite();
  return n;
}

struct Candidate {
  Pose T;
  Fit fit;
};

bool agree(const Pose& a, const Pose& b, const TrustSettings& t) {
  return (a.translation() - b.translation()).norm() <= t.restart_agreement_mm &&
         Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() * 180 / M_PI <= t.restart_agreement_deg;
}
}  // namespace

const char* status_name(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::Ambiguous: return "ambiguous";
    case Status::Failed: return "failed";
  }
  return "?";
}

RegistrationResult register_cloud(const PointCloud& scan_in, const PointCloud& ref_in,
                                  const RegistrationSettings& s) {
  if (finite_points(scan_in) < 10) throw Error("scan has no usable points (empty or all NaN)");
  if (finite_points(ref_in) < 10) throw Error("reference cloud has no usable points");
  const RefineFn refine = find_refiner(s.refine.method);
  RegistrationResult r;
  const double voxel = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref_in);
  r.voxel_mm = voxel;

  auto t = Clock::now();
  PreprocessSettings ref_pre = s.pre;
  ref_pre.use_viewpoint = false, ref_pre.outlier_std = 0;  // CAD samples have no outliers
  const PclCloud::Ptr scan = to_pcl(preprocess(scan_in, s.pre, voxel));
  // The reference keeps its dense CAD samples and exact normals for refinement and assessment
  // (a voxel grid would move points off the surface at edges); without normals, estimate them.
  const PclCloud::Ptr ref = ref_in.has_normals() ? to_pcl(ref_in) : to_pcl(preprocess(ref_in, ref_pre, voxel));
  r.timings_s["preprocess"] = since(t);

  t = Clock::now();
  Tree::Ptr tree(new Tree), ref_tree(new Tree);  // over the scan and the reference
  tree->setInputCloud(scan);
  ref_tree->setInputCloud(ref);
  Features::Ptr ref_f, scan_f;
  PclCloud::Ptr ref_c, scan_c;  // the coarser grid of the RANSAC stage
  const bool coarse = !(s.skip_coarse && s.prior);
  const double cvox = s.coarse.voxel_factor * voxel;
  if (coarse) {
    scan_c = to_pcl(preprocess(scan_in, s.pre, cvox));
    ref_c = to_pcl(preprocess(ref_in, ref_pre, cvox));
    ref_f = fpfh(ref_c, s.coarse.feature_radius_vox * cvox);
    scan_f = fpfh(scan_c, s.coarse.feature_radius_vox * cvox);
  }
  r.timings_s["features"] = since(t);

  const double gate = s.refine.max_correspondence_vox * voxel;
  const double rho_icp = s.rho_icp_vox2 * voxel * voxel;
  std::vector<Candidate> good;  // refined poses with fitness below rho_ICP
  Candidate best{Pose::Identity(), Fit{}};
  best.fit.fitness_mm2 = std::numeric_limits<double>::infinity();  // f*_ICP = 1e6 in the paper
  double t_ransac = 0, t_icp = 0;
  for (int a = 0; a < s.max_attempts; ++a) {
    ++r.attempts;
    Pose T0 = s.prior.value_or(Pose::Identity());
    t = Clock::now();
    if (coarse && (!coarse_align(ref_c, ref_f, scan_c, scan_f, s.coarse, cvox, s.seed + 7919u * a, T0) ||
                   !T0.matrix().allFinite())) {
      t_ransac += since(t);
      continue;
    }
    t_ransac += since(t);
    if (s.q0 && rotation_angle(Eigen::Quaterniond(T0.rotation()), *s.q0) * 180 / M_PI > s.rho_rot_deg)
      continue;  // Algorithm 1, line 5: unrealistic orientation
    t = Clock::now();
    // PCL's least-squares ICP variants divide by a singular matrix when the data cannot fix all
    // six directions (a cylinder seen from the side) and then abort inside PCL on NaN poses; the
    // damped Ceres solve handles it, so degenerate data goes there.
    RefineFn use = refine;
    if (refine != refine_ceres) {
      const Eigen::SelfAdjointEigenSolver<Matrix6d> es(plane_system(*scan, *ref_tree, T0, gate).H);
      if (es.eigenvalues()[0] < 1e-6 * es.eigenvalues()[5]) use = refine_ceres;
    }
    const RefineOutput out = use({ref, scan, tree, ref_tree, T0, voxel, s.refine});
    t_icp += since(t);
    r.iterations += out.iterations;
    if (!out.T.matrix().allFinite()) continue;  // a degenerate solve (e.g. planar data): no pose
    const Candidate c{out.T, evaluate(*scan, *ref_tree, out.T, gate)};
    if (c.fit.fitness_mm2 < best.fit.fitness_mm2) best = c;
    if (c.fit.fitness_mm2 < rho_icp) good.push_back(c);
    // Stop once two converged attempts agree (one when there is no coarse stage to repeat).
    if (!coarse && !good.empty()) break;
    bool agreed = false;
    for (size_t i = 0; i + 1 < good.size() && !agreed; ++i) agreed = agree(good[i].T, good.back().T, s.trust);
    if (agreed) break;
  }
  r.timings_s["ransac"] = t_ransac;
  r.timings_s["refine"] = t_icp;

  t = Clock::now();
  if (!std::isfinite(best.fit.fitness_mm2)) {
    r.status = Status::Failed;
    r.reason = "no RANSAC hypothesis survived (features do not match, or rho_rot rejected all)";
    r.timings_s["assess"] = since(t);
    return r;
  }
  r.T_scan_ref = best.T;
  assess(*scan, *ref_tree, gate, s.trust, voxel, r);
  if (r.status == Status::Ok) {
    // Equally good refined poses that disagree: a symmetry or a repeated structure, not a pose.
    for (const auto& c : good)
      if (!agree(c.T, best.T, s.trust) && c.fit.overlap > 0.9 * best.fit.overlap) {
        r.status = Status::Ambiguous;
        r.reason = "attempts converged to different poses with equal fit (symmetric part?)";
        break;
      }
    if (r.status == Status::Ok && coarse && good.size() < 2 && s.max_attempts >= 2) {
      r.status = Status::Failed;
      r.reason = "no second attempt confirmed the pose (fitness below rho_ICP only once)";
    }
  }
  r.timings_s["assess"] = since(t);
  return r;
}

RegistrationResult register_segmented(const PointCloud& scan, const PointCloud& ref,
                                      const RegistrationSettings& s, int max_clusters, int* cluster) {
  const double voxel = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref);
  // Parts further apart than 3 voxels are separate; a part needs at least a few dozen voxels.
  const auto parts = segment_clusters(scan, voxel, 3 * voxel, 50);
  if (parts.empty()) throw Error("no part of the scan is large enough to register");
  RegistrationResult best;
  int best_i = -1;
  auto rank = [](const RegistrationResult& r) { return r.status == Status::Ok ? 0 : r.status == Status::Ambiguous ? 1 : 2; };
  for (int i = 0; i < int(parts.size()) && i < max_clusters; ++i) {
    if (parts[i].points.size() < 10) continue;
    RegistrationResult r = register_cloud(parts[i], ref, s);
    if (best_i < 0 || rank(r) < rank(best) || (rank(r) == rank(best) && r.fitness_mm2 < best.fitness_mm2))
      best = std::move(r), best_i = i;
  }
  if (cluster) *cluster = best_i;
  best.timings_s["clusters"] = double(parts.size());
  return best;
}

}  // namespace laserfit::registration
