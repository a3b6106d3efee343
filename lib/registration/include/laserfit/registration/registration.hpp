#pragma once
// Registration of a scan against a CAD reference cloud: the paper's Algorithm 1 (filter ->
// FPFH + RANSAC -> orientation gate -> ICP, repeated until the ICP fitness is below rho_ICP) and
// refinement variants, with a trust decision (ok / ambiguous / failed) and a covariance.
// All lengths in mm; T_scan_ref maps reference coordinates into the scan frame.
#include <Eigen/Core>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/registration/settings.hpp"
#include "laserfit/registration/thin.hpp"

namespace laserfit::registration {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

enum class Status { Ok, Ambiguous, Failed };
const char* status_name(Status s);

struct RegistrationResult {
  Pose T_scan_ref = Pose::Identity();
  Status status = Status::Failed;
  std::string reason;      // why ambiguous / failed
  double fitness_mm2 = 0;  // PCL-style ICP fitness: mean squared NN distance (inliers)
  double inlier_rmse_mm = 0;
  double residual_sigma_mm = 0;      // robust (median-based) spread of the same residuals
  double overlap = 0;                // fraction of scan points with a reference point within gate
  int attempts = 0, iterations = 0;  // iterations: ceres and ndt only (PCL ICP does not say)
  Matrix6d covariance = Matrix6d::Zero();           // [rx ry rz (rad), tx ty tz (mm)], scan frame
  Vector6d hessian_eigenvalues = Vector6d::Zero();  // scaled, ascending
  Vector6d weakest_direction = Vector6d::Zero();    // [r (axis, scaled by the part's size) ; t]
  // What the Hessian's directions are about (scan frame): the matched scan points' centroid, and
  // their RMS distance from it, the length a rotation is scaled by (weakest_direction's r is the
  // rotation in rad times it).
  Eigen::Vector3d hessian_centre = Eigen::Vector3d::Zero();
  double hessian_radius_mm = 1;
  int unobservable = 0;  // ambiguous: the directions it names (>= 1; a declared-weak one counts)
  int flat = 0;          // Hessian directions below ambiguity_ratio (declared weak or not)
  // Block-jackknife standard deviations (TrustSettings::jackknife_blocks): of the reference
  // origin's position (largest axis, mm) and of the rotation (largest axis, deg); infinite when
  // too few points were matched to compute them (JSON: null), 0 when the jackknife is off.
  double sigma_origin_mm = 0, sigma_rotation_deg = 0;
  bool not_pinned = false;  // ambiguous because a sigma is above TrustSettings' limit
  // Ambiguous along a translation: where along it (mm from the pose, along its weakest direction)
  // the attempts that fit as well converged; the plateau the slide search covers.
  double flat_from_mm = 0, flat_to_mm = 0;
  double voxel_mm = 0;
  // The candidate part registered: register_segmented's index, kRegrownPart, or -1 (the whole
  // scan).
  int part = -1;
  std::map<std::string, double> timings_s;  // per stage
  std::vector<std::string> log;             // one line per attempt and decision
};

// RegistrationResult::part of a pose registered again on the scan points near the pose found.
inline constexpr int kRegrownPart = -2;

// What a scanner sees of the part placed at T_scan_ref (a view reference, e.g.
// scan::view_reference).
using ViewSampler = std::function<PointCloud(const Pose& T_scan_ref)>;

// The entry point the CLI, the benchmark runner and the controller call: `ref`'s pose in `scan`.
// Segmented (settings.segment) or the whole scan; with `view`, registered once more against the
// view sampled at the pose found (register_in_view). The functions below are its stages.
// Throws laserfit::Error on unusable input (empty or all-NaN clouds, nonsense settings).
RegistrationResult register_scan(const PointCloud& scan, const PointCloud& ref,
                                 const RegistrationSettings& settings,
                                 const ViewSampler& view = {});

// Registers `scan` (organized or not, NaN allowed) against `ref` (with normals).
// Throws laserfit::Error on unusable input (empty or all-NaN clouds, nonsense settings).
RegistrationResult register_cloud(const PointCloud& scan, const PointCloud& ref,
                                  const RegistrationSettings& settings);

// Standard deviation along its largest axis (mm) of a point `oc` away from the centre a pose
// covariance ([rx ry rz (rad, about that centre), tx ty tz (mm)]) is taken about: the reference
// origin's for RegistrationResult::covariance with oc = origin - matched points' centroid.
double origin_sigma_mm(const Matrix6d& covariance, const Eigen::Vector3d& oc);
// Largest standard deviation of a 3x3 covariance (infinite if it is not finite).
double top_sigma(const Eigen::Matrix3d& covariance);

// For an `ambiguous` result: is its weakest direction a rotation about / a translation along
// `axis` (scan frame, unit), within `tol_deg`? (Which DoF the scan could not fix.)
bool weakest_is_rotation_about(const RegistrationResult& r, const Eigen::Vector3d& axis,
                               double tol_deg = 10);
bool weakest_is_translation_along(const RegistrationResult& r, const Eigen::Vector3d& axis,
                                  double tol_deg = 10);
// r's pose moved along its weakest direction (a screw about hessian_centre) as far as `toward`
// lies along it, to first order: the directions the scan pins keep r's values, the one it does
// not takes toward's (say an earlier measurement of an object that has not moved).
Pose along_weakest_to(const RegistrationResult& r, const Pose& toward);

// The unit vector of the reference-frame axis named "x", "y" or "z" (how cells, benchmarks and
// the CLI name a weak DoF); nullopt for "" (none). Throws laserfit::Error on any other name.
std::optional<Eigen::Vector3d> named_axis(const std::string& name);

// Splits a scan into parts by Euclidean clustering of its downsampled points (gap larger than
// `tolerance_mm`), largest first; each part is returned at full resolution (the scan points in
// the cluster's bounding box grown by one voxel). Clusters under `min_points` are dropped.
std::vector<PointCloud> segment_clusters(const PointCloud& scan, double voxel_mm,
                                         double tolerance_mm, size_t min_points = 50);

// The scan points within `radius_mm` of `ref` placed at `T_scan_ref` (unorganized), or of the
// reference slid from there by any translation between `slide_from_mm` and `slide_to_mm` (scan
// frame).
PointCloud crop_near(const PointCloud& scan, const PointCloud& ref, const Pose& T_scan_ref,
                     double radius_mm,
                     const Eigen::Vector3d& slide_from_mm = Eigen::Vector3d::Zero(),
                     const Eigen::Vector3d& slide_to_mm = Eigen::Vector3d::Zero());

// Registers `ref` against up to `max_clusters` parts of the scan — with a prior, first the points
// near the reference placed there (crop_near), then the clusters nearest it; else the largest
// first — stopping at the first `ok`; returns the best (ok before
// ambiguous before failed, then lowest fitness); `cluster` receives its index. A best result with
// unobservable directions is refined once more on the scan points near the pose found (a part
// cut in two by a shadow); when that is better, `cluster` is kRegrownPart.
RegistrationResult register_segmented(const PointCloud& scan, const PointCloud& ref,
                                      const RegistrationSettings& settings, int max_clusters = 4,
                                      int* cluster = nullptr);

// A view reference depends on the pose it is seen at. Sampled at the prior, it shows walls that a
// part turned away from the prior no longer shows and lacks those it turned toward; a socket
// turned by 15-20 deg fitted its scan at 8-24 um RMS instead of 2.5 um, and RANSAC, matching
// FPFH of the other view, never confirmed the right pose (registration.yaml's receptacle).
// register_segmented with `ref`, then, when that found a pose, once more with `view` sampled at it
// (that pose as the prior); the second answer is kept unless it failed where the first did not.
// Thin parts are detected, not registered: one pass.
RegistrationResult register_in_view(const PointCloud& scan, const PointCloud& ref,
                                    const ViewSampler& view, const RegistrationSettings& settings,
                                    int max_clusters = 4);

// Does `ref` go to the thin-part detector (settings.thin.mode, and for auto its thin_profile)?
// register_cloud and register_segmented dispatch there themselves.
bool uses_thin_detector(const PointCloud& ref, const RegistrationSettings& settings);

// Locates a thin part's tip and axis (thin.hpp): `ambiguous` (its spin is unobservable) with the
// pose, or `failed` with the candidates' reasons. Needs settings.prior (or at least q0: then
// exactly one thin candidate along it must be found).
RegistrationResult detect_thin_part(const PointCloud& scan, const PointCloud& ref,
                                    const RegistrationSettings& settings);

}  // namespace laserfit::registration
