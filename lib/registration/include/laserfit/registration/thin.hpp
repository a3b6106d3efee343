#pragma once
// Thin parts (a 150 um thread): FPFH needs a neighbourhood several voxels wide, wider than the
// thread, and ICP slides freely along it, so Algorithm 1 cannot register such a part. Instead its
// tip is *detected*: the scan's thin, elongated clusters near the prior are checked against the
// band a part of the reference's radius shows and fitted with a cylinder of that radius (Ceres,
// robust loss, axis leaning on the prior's); the tip is the fitted axis at the end of the seen
// points. The paper picked the tip by hand in a GUI.
// A thin reference follows the thread_tip convention: its axis is its own z, the tip at max z.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/enum_names.hpp"

namespace laserfit::registration {

// auto: thin references (ThinSettings' diameter and aspect) are detected, not registered; on:
// every reference; off: never.
enum class ThinMode { Auto, On, Off };

struct ThinSettings {
  ThinMode mode = ThinMode::Auto;
  double max_diameter_mm = 0.5;    // auto: a reference at most this thick ...
  double min_aspect = 5.0;         // ... and at least this many diameters long is thin
  double search_radius_mm = 10.0;  // candidates within this of the prior-placed reference's axis
                                   // (the prior's error: an arm off by mm after an IC2 approach)
  double linear_radius_mm = 0.25;  // neighbourhood for telling line points from surfaces ...
  double max_cross_ratio = 0.35;   // ... a line's second principal spread is below this x the first
  double cluster_tolerance_mm = 0.25;  // line points further apart are separate candidates (a
                                       // thread returns nothing from some profiles)
  int min_points = 15;                 // per candidate
  double fit_length_mm = 2.0;          // the cylinder is fitted to this much behind the seen tip
  double min_length_mm = 0.3;          // seen length of a candidate along its axis
  double max_axis_deg = 30.0;   // candidate axis within this of the prior's (a +-20 deg prior)
  double axis_prior_deg = 2.0;  // the prior's axis is this good (sigma): the gripper holds the
                                // thread straight; 0 = fit the axis freely
  bool fit_radius = false;      // fit the radius too (else the reference's, see cylinder_fit.cpp)
  double radius_tolerance = 0.35;  // with fit_radius: within this fraction of the reference's
  double max_rmse_mm = 0.012;      // cylinder-fit residual RMS (sensor noise is ~2 um)
  double min_inlier_fraction =
      0.5;  // of the candidate's points within 3 robust scales (the rim of
            // the cut end, a short line across the axis, is in the cluster)
};

struct ThinProfile {
  bool thin = false;
  double radius_mm = 0, length_mm = 0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // axis point at max z (reference frame)
};
// The reference's cross-section radius (median distance of its points from the z axis through
// their centroid) and length along z.
ThinProfile thin_profile(const PointCloud& ref, const ThinSettings& s);

struct CylinderFit {
  bool converged = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // on the axis
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit
  double radius_mm = 0, rmse_mm = 0;                // rmse over the inliers
  double inlier_fraction = 0;
  Eigen::Matrix<double, 5, 5> covariance =
      Eigen::Matrix<double, 5, 5>::Zero();  // of the parameters
                                            // [u v (mm, across), alpha beta (rad), r (mm)]
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();  // their directions
  std::vector<char> inlier;                                                      // per input point
};
struct CylinderFitOptions {
  bool fix_radius = false;    // hold r at radius0 (a narrow arc hardly fixes it)
  double axis_sigma_rad = 0;  // > 0: Gaussian prior of the axis about axis0 (rad)
  double noise_mm = 0.003;    // the points' noise across the surface (whitens the residuals)
};
// Least-squares cylinder through `pts` (only the side facing the sensor need be seen): residual
// |distance to the axis| - r under a Huber loss of scale `robust_mm`, from an axis guess.
CylinderFit fit_cylinder(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& point0,
                         const Eigen::Vector3d& axis0, double radius0, double robust_mm,
                         const CylinderFitOptions& options = {});

}  // namespace laserfit::registration

namespace laserfit {
template <>
struct EnumNames<registration::ThinMode> {
  static constexpr const char* what = "thin mode";
  static constexpr std::pair<registration::ThinMode, const char*> table[] = {
      {registration::ThinMode::Auto, "auto"},
      {registration::ThinMode::On, "on"},
      {registration::ThinMode::Off, "off"}};
};
}  // namespace laserfit
