#pragma once
// The stages of Algorithm 1 (private to lib/registration).
#include <pcl/PointIndices.h>
#include <pcl/features/fpfh.h>

#include "laserfit/registration/registration.hpp"
#include "pcl_types.hpp"

namespace laserfit::registration {

// Pre-processing pieces (preprocess.cpp). sample_and_filter: one real point per voxel, then
// statistical outlier removal. with_normals: normals of `cloud` from its neighbours in `surface`
// within `radius`, points without one dropped, oriented towards the viewpoint (s.use_viewpoint)
// or to the side of the normal each point carried (keep_side). coarser: the voxel-grid cloud
// of the RANSAC stage with normals from the fine cloud.
PclCloud::Ptr sample_and_filter(const PointCloud& c, const PreprocessSettings& s, double voxel);
PclCloud::Ptr with_normals(const PclCloud::Ptr& cloud, const PclCloud::Ptr& surface, double radius,
                           const PreprocessSettings& s, bool keep_side);
PclCloud::Ptr coarser(const PclCloud::Ptr& fine, double cvox, const PreprocessSettings& s,
                      bool keep_side);
// Euclidean clusters of `cloud` (gap above tolerance_mm), at least min_points each, largest first:
// pcl::EuclideanClusterExtraction's answer for a cloud without coincident points (segment.cpp).
std::vector<pcl::PointIndices> euclidean_clusters(const PclCloud::Ptr& cloud, double tolerance_mm,
                                                  size_t min_points);
// preprocess() in PCL types (what the stages consume); throws Error when too little is left.
PclCloud::Ptr prepare(const PointCloud& in, const PreprocessSettings& s, double voxel);

using Features = pcl::PointCloud<pcl::FPFHSignature33>;
Features::Ptr fpfh(const PclCloud::Ptr& cloud, double radius_mm);

// One RANSAC attempt (Algorithm 1, line 4): FPFH correspondences, SampleConsensusPrerejective.
// Seeded; returns false when no hypothesis reached the inlier fraction.
bool coarse_align(const PclCloud::Ptr& ref, const Features::Ptr& ref_f, const PclCloud::Ptr& scan,
                  const Features::Ptr& scan_f, const CoarseSettings& s, double voxel, uint64_t seed,
                  Pose& T_scan_ref);

// Correspondences for a pose T (scan frame): each scan point q with its nearest reference point,
// kept when within `gate` and, when the scan normals face the sensor, when the reference normal
// does not face away from it: that drops matches through a thin wall (the far side of a 0.35 mm
// USB shell). Matches across an edge are kept: they are what penalises sliding along a face.
struct Match {
  Eigen::Vector3d p, q, n;  // model point T*m, scan point, model normal R*n_m (scan frame)
};
struct Matcher {
  double gate = 0;        // mm
  bool oriented = false;  // scan normals face the sensor and reference normals face outwards
};
std::vector<Match> match(const PclCloud& scan, const Tree& ref_tree, const Pose& T,
                         const Matcher& m);

// The same with the orientation gate applied to every hypothesis (coarse_gated.cpp); without q0
// it is plain RANSAC over FPFH correspondences.
bool coarse_align_gated(const PclCloud::Ptr& ref, const Features::Ptr& ref_f,
                        const PclCloud::Ptr& scan, const Features::Ptr& scan_f,
                        const CoarseSettings& s, double voxel, uint64_t seed,
                        const std::optional<Eigen::Quaterniond>& q0, double rho_rot_deg,
                        Pose& T_scan_ref);

// Refinement (Algorithm 1, line 6) with the named variant.
struct RefineInput {
  PclCloud::Ptr ref, scan;  // ref: dense CAD samples with their exact normals
  Tree::Ptr scan_tree, ref_tree;
  Pose init;
  double voxel;
  const RefineSettings& s;
  bool oriented;  // see Matcher
};
struct RefineOutput {
  Pose T = Pose::Identity();
  int iterations = 0;
};
using RefineFn = RefineOutput (*)(const RefineInput&);
RefineFn refiner_fn(Refiner r);

// The variants, one small file each (refine_*.cpp); registered in refiners.cpp.
RefineOutput refine_point_to_point(const RefineInput& in);
RefineOutput refine_point_to_plane(const RefineInput& in);
RefineOutput refine_gicp(const RefineInput& in);
RefineOutput refine_ndt(const RefineInput& in);
RefineOutput refine_ceres(const RefineInput& in);

// Fit statistics and the trust decision for a final pose, measured from the scan side: the scan
// (one view, segmented to the object) should lie on the reference, while most of the reference
// is legitimately unseen. fitness = mean squared point-to-plane distance (reference normals) of
// the scan points whose nearest reference point is within the gate — with dense CAD samples this
// measures misalignment, not sampling density; overlap = fraction of scan points within the gate.
struct Fit {
  double fitness_mm2 = 0, rmse_mm = 0, overlap = 0;
  size_t inliers = 0;
};
Fit evaluate(const PclCloud& scan, const Tree& ref_tree, const Pose& T_scan_ref, const Matcher& m);
// "As good a fit" as another pose: at least 98 % of its overlap and at most 1.5x its fitness. A
// pose that leaves a few percent of the scan unexplained (a hole matched to the wrong hole, a
// needle slid off its eye) is worse, not an equal. The one rule for rivals, for choosing by the
// prior among attempts, and for pinned slides.
// Fit and RegistrationResult both carry overlap and fitness_mm2.
template <class A, class B>
bool fits_as_well(const A& a, const B& than) {
  return a.overlap >= 0.98 * than.overlap && a.fitness_mm2 <= 1.5 * than.fitness_mm2;
}
// The point-to-plane normal equations at pose T (scaled Hessian H, residual sum, RMS radius L).
struct PlaneSystem {
  Matrix6d H = Matrix6d::Zero();
  double residual2 = 0, L = 1;
  size_t n = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  // the matched scan points' centroid
  std::vector<Match> matches;
};
PlaneSystem plane_system(const PclCloud& scan, const Tree& ref_tree, const Pose& T,
                         const Matcher& m);
// 1.4826 x the median absolute point-to-plane residual: the residuals' spread as noise alone
// would give it, blind to a minority of misfits (mm).
double robust_sigma(const std::vector<Match>& matches);
// The same of absolute residuals (reordered; not empty).
double robust_sigma_of(std::vector<double>& abs_residuals);
void assess(const PclCloud& scan, const Tree& ref_tree, const Matcher& m, const TrustSettings& t,
            double voxel, RegistrationResult& r);
// An `ok` whose jackknife sigma (set by assess) is above the trust limits -> ambiguous, not
// pinned. Last, after the rival and confirmation checks: a wrong pose those fail stays failed.
void check_pinned(const TrustSettings& t, RegistrationResult& r);
// Block-jackknife covariance of the pose ([rx ry rz (rad, about c), tx ty tz (mm)]) from the
// matches at the final pose, per_axis^2 blocks (jackknife.cpp); nullopt with too few matches.
std::optional<Matrix6d> block_jackknife(const std::vector<Match>& M, const Eigen::Vector3d& c,
                                        double L, int per_axis);

}  // namespace laserfit::registration
