#pragma once
// Settings of the registration, one struct per stage with its defaults in class (units in the
// names or comments), choices as enums named once (laserfit/core/enum_names.hpp). All lengths mm.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>

#include "laserfit/core/enum_names.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/registration/thin.hpp"

namespace laserfit::registration {

// The coarse stage (Algorithm 1, line 4). gated: rho_rot tested on every RANSAC hypothesis; pcl:
// PCL's SampleConsensusPrerejective, rho_rot tested on its result (the paper).
enum class CoarseMethod { Gated, Pcl };
// The refinement (Algorithm 1, line 6): PCL's ICP variants, or laserfit's robust point-to-plane
// solve over Ceres.
enum class Refiner { PointToPoint, PointToPlane, Gicp, Ndt, Ceres };
enum class RobustLoss { Huber, Cauchy, Tukey, None };  // of the Ceres refinement
// A method as benchmarks and the CLI name it: a refiner with laserfit's policies, or `paper`
// (Algorithm 1 as published: PCL's SampleConsensusPrerejective and point-to-point ICP, policies
// off).
enum class Method { Paper, PointToPoint, PointToPlane, Gicp, Ndt, Ceres };

struct PreprocessSettings {
  double voxel_mm = 0.0;           // voxel grid leaf; 0 = auto (reference bbox diagonal / 150)
  int outlier_neighbours = 20;     // statistical outlier removal: k neighbours ...
  double outlier_std = 2.0;        // ... and the std-dev multiplier (0 disables the filter)
  double normal_radius_vox = 3.0;  // normal estimation radius, in voxels
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // normals are flipped towards it (mm)
  bool use_viewpoint = false;  // scan clouds: towards the sensor; references keep their own
};

struct CoarseSettings {
  CoarseMethod method = CoarseMethod::Gated;
  double voxel_factor = 2.0;           // features and RANSAC run on a grid this much coarser
  double feature_radius_vox = 6.0;     // FPFH radius, in voxels
  int ransac_iterations = 10000;       // SampleConsensusPrerejective iterations per attempt
  int samples = 3;                     // correspondences per hypothesis
  int correspondence_randomness = 10;  // k nearest features to pick from
  double similarity = 0.85;            // edge-length similarity for pre-rejection (0..1)
  double inlier_fraction = 0.25;       // of the (segmented) scan, for a hypothesis to be accepted
  double max_correspondence_vox = 2.5;
};

struct RefineSettings {
  Refiner method = Refiner::Ceres;
  double max_correspondence_vox = 2.0;         // ICP correspondence gate, in voxels
  double initial_gate_mm = 1.0;                // ceres: first gate at least this (a prior's error)
  int max_iterations = 60;                     // per scale (ceres) / in total (PCL variants)
  double convergence_mm = 1e-4;                // stop when the update moves points less than this
  RobustLoss robust_loss = RobustLoss::Huber;  // ceres
  double robust_scale_vox = 0.1;  // ceres: robust loss scale at the finest gate, in voxels
                                  // (x4, x2 at the coarser gates)
};

struct TrustSettings {
  double max_rmse_vox = 0.5;      // inlier RMSE above this (in voxels) -> failed
  double min_overlap = 0.3;       // fraction of the reference explained -> else failed
  double ambiguity_ratio = 1e-3;  // Hessian eigenvalue ratio (scaled) below -> ambiguous
  // DoFs the task declares weak for this reference (its frame, unit; a needle's spin about its
  // shaft, a plug's slide along itself): ambiguous about them below the looser ratio. Just above
  // ambiguity_ratio (1.4e-3 to 3.5e-3) a needle's spin came back `ok` up to 1 deg off and a
  // plug's slide 57 um off; the USB receptacle, pinned everywhere, stays above 3e-3.
  std::optional<Eigen::Vector3d> weak_rotation, weak_translation;
  double declared_weak_ratio = 1e-2;
  // Block jackknife (jackknife.cpp): the pose re-solved with each of blocks^2 spatial blocks of
  // the matched scan left out. Its spread, at the reference's origin, counts correlated
  // residuals that sigma^2 H^-1 misses; above either limit -> ambiguous (0 = no limit). The
  // limits are the success tolerance: a pose whose origin moves by more than that when
  // one region is dropped is not known to that tolerance. On the o2ac panel (a 20 x 25 mm window
  // 37 mm from its origin, the in-plane rotation pinned by two hole outlines) every wrong `ok`
  // of 60 trials had sigma 0.23-2.9 mm; USB and needle poses stay under 12 um.
  int jackknife_blocks = 4;            // per principal axis of the matched points
  double max_sigma_mm = 0.05;          // jackknife sigma of the reference origin's position
  double max_sigma_deg = 0.5;          // jackknife sigma of the rotation
  double restart_agreement_mm = 0.02;  // restarts agree when the reference's points move less
                                       // than this (RMS along their normals) between them
  double polish_mm = 0.02;             // a robust point-to-plane polish of the final pose must move
  double polish_deg = 0.2;             // it less than this, else failed (non-Ceres refiners)
  // Slide search (slide.cpp): a pose flat along a translation not declared weak is refined again
  // from poses slid along it by +-step, +-2 step ... up to the range, and a re-refinement the data
  // pin is kept (mm; range 0 = off). A needle's eye is 1 mm long: steps well under it.
  double slide_step_mm = 0.25;
  double slide_range_mm = 2.0;
  // An ok no second attempt confirmed (refinement from the prior only) must have residuals that
  // look like noise: inlier RMSE at most this x their robust sigma (1.4826 x median |residual|).
  // At the true pose the ratio is 1-1.6 on the o2ac panel's visible band and reaches ~7 where
  // its shiny faces throw outliers; a pose slid 9.5 mm along the plate fits 98 % of the scan to
  // 3 um and the rest to ~0.5 mm: ratio 27.
  double max_rmse_to_sigma = 10.0;
  double rmse_floor_mm = 0.005;  // an RMSE below this is noise whatever the ratio (a noise-free
                                 // simulation has a sigma near 0)
  // Twins (twins.cpp): motions that lay at least twin_self_overlap of the reference back onto
  // itself are its near-symmetries. An ok pose turned by one, when that explains at least
  // twin_screen of what the pose found explains of a scan subsample, is refined (the max_twins
  // that explain most of it). The scan tells the twin apart when the points on the reference at
  // the pose found (within 3 robust sigmas) and off it at the twin's (beyond twin_off_mm, or
  // unmatched) outnumber those the other way round by more than twin_evidence of the scan and
  // more than the other way's own count (what sampling alone gives). Else -> ambiguous; the
  // other way round, the twin replaces the pose. A 2 x 2 x 1 mm boss on a 20 mm frustum's view:
  // 0.56 % one way, 0.21 % the other; a bearing housing's twin with its boss out of view: 1.8 %
  // and 1.6 %.
  double twin_self_overlap = 0.7;
  double twin_screen = 0.9;
  int max_twins = 8;
  double twin_evidence = 0.002;
  double twin_off_mm = 0.05;
};

// register_scan splits the scan into candidate parts (register_segmented) unless switched off.
struct SegmentSettings {
  bool enabled = true;   // off: the whole scan is the part (register_cloud)
  int max_clusters = 4;  // candidate parts tried, nearest the prior (else largest) first
};

// What laserfit adds to Algorithm 1 for its trust decision, each a stage that can be switched off
// (docs/design/registration.md has the measurement behind each). Two more are switched off by
// their own settings: the slide search by trust.slide_range_mm = 0, the block jackknife by
// trust.jackknife_blocks = 0; thin-part detection by thin.mode = ThinMode::Off.
struct Policies {
  bool paper = false;  // Algorithm 1's own choices: keep the lowest fitness (not among the
                       // attempts explaining most of the scan), rho_rot on the RANSAC pose only
  bool prefer_prior =
      true;             // ambiguous: of the attempts that fit as well, the one nearest the prior
  bool polish = true;   // non-Ceres refiners: an ok must sit at the robust point-to-plane minimum
  bool rivals = true;   // attempts that fit as well but disagree -> ambiguous
  bool confirm = true;  // an ok needs a second attempt that agrees with it
  bool consistent = true;  // refine-only: an ok's residuals must look like noise (no misfit tail)
  bool twins = true;       // ok: a twin turned by the part's near-symmetry fits too -> ambiguous
  bool regrow = true;      // segmented, ambiguous: registered again on all scan points near it
  bool view = true;        // register_in_view: once more against the view seen at the pose found
};

struct RegistrationSettings {
  PreprocessSettings pre;
  CoarseSettings coarse;
  RefineSettings refine;
  TrustSettings trust;
  ThinSettings thin;  // thin parts (a thread) are detected, not registered
  Policies policies;
  SegmentSettings segment;
  // Algorithm 1 of the paper.
  double rho_icp_vox2 = 0.05;  // stop when ICP fitness (mean squared distance) < rho * voxel^2
  double rho_rot_deg = 30.0;   // reject RANSAC poses farther than this from q0
  std::optional<Eigen::Quaterniond> q0;  // prior orientation of the reference in the scan frame
  std::optional<Pose> prior;             // prior pose (e.g. from the arm's kinematics): the first
                              // hypothesis, then RANSAC; refinement only with skip_coarse
  bool skip_coarse = false;
  double prior_radius_mm = 1.0;  // segmentation: scan points this near the reference placed
                                 // at the prior are a candidate part (the prior's error)
  int max_attempts = 8;          // RANSAC + ICP rounds before giving up
  uint64_t seed = 1;
};

// The settings of a method: `paper` sets the coarse stage, the refiner and Policies::paper; the
// others set the refiner.
void apply_method(RegistrationSettings& s, Method m);
// The method these settings amount to (Paper when policies.paper).
Method method_of(const RegistrationSettings& s);

}  // namespace laserfit::registration

namespace laserfit {
template <>
struct EnumNames<registration::CoarseMethod> {
  static constexpr const char* what = "coarse method";
  static constexpr std::pair<registration::CoarseMethod, const char*> table[] = {
      {registration::CoarseMethod::Gated, "gated"}, {registration::CoarseMethod::Pcl, "pcl"}};
};
template <>
struct EnumNames<registration::Refiner> {
  static constexpr const char* what = "refiner";
  static constexpr std::pair<registration::Refiner, const char*> table[] = {
      {registration::Refiner::PointToPoint, "point_to_point"},
      {registration::Refiner::PointToPlane, "point_to_plane"},
      {registration::Refiner::Gicp, "gicp"},
      {registration::Refiner::Ndt, "ndt"},
      {registration::Refiner::Ceres, "ceres"}};
};
template <>
struct EnumNames<registration::RobustLoss> {
  static constexpr const char* what = "robust loss";
  static constexpr std::pair<registration::RobustLoss, const char*> table[] = {
      {registration::RobustLoss::Huber, "huber"},
      {registration::RobustLoss::Cauchy, "cauchy"},
      {registration::RobustLoss::Tukey, "tukey"},
      {registration::RobustLoss::None, "none"}};
};
template <>
struct EnumNames<registration::Method> {
  static constexpr const char* what = "registration method";
  static constexpr std::pair<registration::Method, const char*> table[] = {
      {registration::Method::Paper, "paper"},
      {registration::Method::PointToPoint, "point_to_point"},
      {registration::Method::PointToPlane, "point_to_plane"},
      {registration::Method::Gicp, "gicp"},
      {registration::Method::Ndt, "ndt"},
      {registration::Method::Ceres, "ceres"}};
};
}  // namespace laserfit
