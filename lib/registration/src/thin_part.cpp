// Thin-part detection (see thin.hpp): candidates are Euclidean clusters of the scan near the
// prior-placed reference's axis; a candidate must be elongated along the prior's axis, fit a
// cylinder of the reference's radius, and be the one nearest the prior's tip.
#include <pcl/segmentation/extract_clusters.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <unordered_map>

#include "laserfit/core/error.hpp"
#include "laserfit/registration/preprocess.hpp"
#include "laserfit/registration/registration.hpp"
#include "pcl_types.hpp"

namespace laserfit::registration {
namespace {

struct Candidate {
  CylinderFit fit;
  Eigen::Vector3d tip, data_tip;  // axis point at the tip; the seen point furthest along the axis
  double length_mm = 0, spacing_mm = 0, distance_mm = 0;
};

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
  return (p - a - t * ab).norm();
}

// Centroid, principal direction (oriented along `a0`) and the spread across it (two std-devs).
void principal_axis(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& a0,
                    Eigen::Vector3d& mean, Eigen::Vector3d& axis, Eigen::Vector2d& cross) {
  mean.setZero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov / double(pts.size()));
  axis = es.eigenvectors().col(2);
  if (axis.dot(a0) < 0) axis = -axis;
  cross = es.eigenvalues().head<2>().cwiseMax(0).cwiseSqrt();
}

// The points whose neighbourhood is a line, not a surface: a thread seen from the side is a
// band of one to a few points per profile, the needle beside it a grid. Drops the surfaces a
// thread tip comes close to (the needle under it) so that clustering can bridge the profiles
// where the thread returned nothing.
// The neighbourhood's shape is read from one centroid per occupied voxel (a fifth of the radius),
// not from the raw points, so that it does not depend on how densely the part was seen: with the
// raw points and a cap on their number, the nearest points of a thread seen broadside at a high
// density spanned ~0.13 x 0.36 mm of its band, too wide for a line, and the thread was not found
// (in 6 of the needle suite's trials).
std::vector<int> linear_points(const PclCloud& cloud, const ThinSettings& t) {
  const double v = t.linear_radius_mm / 5;
  std::unordered_map<std::int64_t, int> voxel_index;
  std::vector<int> voxel_of(cloud.size());
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> count;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud[i].getVector3fMap().cast<double>();
    const Eigen::Array3d c = (p / v).array().floor();
    // 21 bits per axis: +-1e6 voxels, metres at this size.
    const std::int64_t key = ((std::int64_t(c.x()) & 0x1FFFFF) << 42) |
                             ((std::int64_t(c.y()) & 0x1FFFFF) << 21) |
                             (std::int64_t(c.z()) & 0x1FFFFF);
    const auto [it, added] = voxel_index.emplace(key, int(sum.size()));
    if (added) sum.emplace_back(Eigen::Vector3d::Zero()), count.push_back(0);
    voxel_of[i] = it->second;
    sum[it->second] += p, ++count[it->second];
  }
  const PclCloud::Ptr centroids(new PclCloud);
  for (size_t k = 0; k < sum.size(); ++k) {
    PointT c;
    c.getVector3fMap() = (sum[k] / count[k]).cast<float>();
    centroids->push_back(c);
  }
  Tree tree;
  tree.setInputCloud(centroids);
  std::vector<char> line(centroids->size(), 0);
  pcl::Indices idx;
  std::vector<float> d2;
  for (size_t k = 0; k < centroids->size(); ++k) {
    if (tree.radiusSearch(centroids->at(k), t.linear_radius_mm, idx, d2) < 5) continue;
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int j : idx) m += centroids->at(j).getVector3fMap().cast<double>();
    m /= double(idx.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int j : idx) {
      const Eigen::Vector3d d = centroids->at(j).getVector3fMap().cast<double>() - m;
      cov += d * d.transpose();
    }
    const Eigen::Vector3d ev =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
    line[k] = ev[1] <= t.max_cross_ratio * t.max_cross_ratio * ev[2];
  }
  std::vector<int> keep;
  for (size_t i = 0; i < cloud.size(); ++i)
    if (line[voxel_of[i]]) keep.push_back(int(i));
  return keep;
}

std::string find_tip(const std::vector<Eigen::Vector3d>& pts,
                     const std::vector<Eigen::Vector3f>& near, const ThinSettings& t, Candidate& c);

// Why a cluster is not the part, or "" and the candidate.
std::string assess(const std::vector<Eigen::Vector3d>& all,
                   const std::vector<Eigen::Vector3f>& near, const ThinProfile& prof,
                   const Eigen::Vector3d& a0, const RegistrationSettings& s, Candidate& c) {
  const ThinSettings& t = s.thin;
  Eigen::Vector3d mean, axis;
  Eigen::Vector2d cross;
  principal_axis(all, a0, mean, axis, cross);
  if (std::acos(std::min(1.0, axis.dot(a0))) > t.max_axis_deg * M_PI / 180)
    return "not along the prior's axis";
  // Only the last fit_length_mm behind the tip: a real thread bends further back.
  double s_max = -INFINITY;
  for (const auto& p : all) s_max = std::max(s_max, axis.dot(p - mean));
  std::vector<Eigen::Vector3d> pts;
  for (const auto& p : all)
    if (axis.dot(p - mean) >= s_max - t.fit_length_mm) pts.push_back(p);
  if (pts.size() < size_t(t.min_points)) return "too few points near its end";
  principal_axis(pts, a0, mean, axis, cross);
  // The seen band across the axis: a cylinder of radius r seen over +-theta of its circumference
  // shows a band of standard deviation ~0.58 r sin(theta); a thread is seen over +-15..80 deg.
  // (The radius itself is barely observable from such an arc: see cylinder_fit.cpp.)
  if (cross.maxCoeff() > prof.radius_mm) return "wider than the reference";
  if (cross.maxCoeff() < 0.15 * prof.radius_mm) return "narrower than the reference";
  // Start on the axis: the seen band of the surface faces the sensor, r in front of the axis.
  Eigen::Vector3d start = mean;
  if (s.pre.use_viewpoint) {
    Eigen::Vector3d away = mean - s.pre.viewpoint;
    away -= axis * axis.dot(away);
    if (away.norm() > 0) start += away.normalized() * prof.radius_mm;
  }
  std::ostringstream why;
  CylinderFitOptions fo;
  fo.fix_radius = !t.fit_radius;
  fo.axis_sigma_rad = t.axis_prior_deg * M_PI / 180;
  // Start from (and, with a prior sigma, lean on) the prior's direction, through the points.
  c.fit = fit_cylinder(pts, start, t.axis_prior_deg > 0 ? a0 : axis, prof.radius_mm, 0.004, fo);
  const CylinderFit& f = c.fit;
  if (!f.converged) return "cylinder fit did not converge";
  if (t.fit_radius && std::abs(f.radius_mm / prof.radius_mm - 1) > t.radius_tolerance) {
    why << "radius " << f.radius_mm << " mm, reference " << prof.radius_mm;
    return why.str();
  }
  if (f.rmse_mm > t.max_rmse_mm)
    return (why << "cylinder residual " << f.rmse_mm * 1e3 << " um", why.str());
  if (f.inlier_fraction < t.min_inlier_fraction)
    return (why << "inliers " << f.inlier_fraction, why.str());
  if (std::acos(std::min(1.0, std::abs(f.axis.dot(a0)))) > t.max_axis_deg * M_PI / 180)
    return "fitted axis off the prior's";
  c.fit.axis = f.axis.dot(a0) < 0 ? Eigen::Vector3d(-f.axis) : f.axis;
  return find_tip(pts, near, t, c);
}

// The seen length, the axial sampling and the tip of a fitted candidate (c.fit, its axis pointing
// to the tip), or why it is too short.
std::string find_tip(const std::vector<Eigen::Vector3d>& pts,
                     const std::vector<Eigen::Vector3f>& near, const ThinSettings& t,
                     Candidate& c) {
  const CylinderFit& f = c.fit;
  const Eigen::Vector3d a = f.axis;
  std::ostringstream why;
  std::vector<double> s_ax;
  for (size_t i = 0; i < pts.size(); ++i)
    if (f.inlier[i]) s_ax.push_back(a.dot(pts[i] - f.point));
  std::sort(s_ax.begin(), s_ax.end());
  c.length_mm = s_ax.back() - s_ax.front();
  if (c.length_mm < t.min_length_mm)
    return (why << "seen over " << c.length_mm << " mm only", why.str());
  // Axial sampling (profiles cross the part at steps along it): the 90th percentile of the gaps.
  std::vector<double> gaps;
  for (size_t i = 1; i < s_ax.size(); ++i) gaps.push_back(s_ax[i] - s_ax[i - 1]);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() * 9 / 10, gaps.end());
  c.spacing_mm = gaps[gaps.size() * 9 / 10];
  // The last profile that hit the part ends on average half a profile step short of its end:
  // the step is the typical gap between profiles (gaps within a profile are ~0).
  std::vector<double> steps;
  for (double g : gaps)
    if (g > 0.25 * c.spacing_mm) steps.push_back(g);
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double step = steps.empty() ? 0.0 : steps[steps.size() / 2];
  // The end of the band as the line test saw it is short of the seen end: there the neighbourhood
  // holds the band on one side only, half as long for its width, and a band seen broadside is
  // too wide for a line over its last ~0.1 mm (the tip measured 90-180 um short in the needle
  // suite). So the scan's points on the fitted cylinder's surface just
  // beyond it are the part's too.
  const double band = std::max(3 * f.rmse_mm, 0.005), last = s_ax.back();
  for (const auto& q : near) {
    const Eigen::Vector3d d = q.cast<double>() - f.point;
    const double along = a.dot(d);
    if (along > last && along <= last + t.cluster_tolerance_mm &&
        std::abs((d - a * along).norm() - f.radius_mm) < band)
      s_ax.push_back(along);
  }
  std::sort(s_ax.begin(), s_ax.end());
  // The seen end: the last point not cut off from the rest by a gap of more than two steps.
  // Stray points beyond the end (mixed pixels or outliers of the surface under the tip that
  // happen to lie on the cylinder's band) are cut off so; taken as the end, they put the tip
  // 0.15-0.36 mm too far (seen in the controller campaign).
  size_t end = s_ax.size() - 1;
  while (step > 0 && end >= 1 && s_ax[end] - s_ax[end - 1] > 2 * step) --end;
  c.data_tip = f.point + a * s_ax[end];
  c.tip = c.data_tip + a * (step / 2);
  return "";
}

// Covariance of [rotation (rad, about the tip), tip (mm)] from the fit's parameters, plus the
// spin about the axis (unknown: uniform over +-pi) and the tip's position along the axis
// (uniform over one axial sampling step).
Matrix6d tip_covariance(const Candidate& c) {
  const CylinderFit& f = c.fit;
  auto eval = [&](const Eigen::Matrix<double, 5, 1>& x) {
    const Eigen::Vector3d p = f.point + x[0] * f.e1 + x[1] * f.e2;
    const Eigen::Vector3d a = (f.axis + x[2] * f.e1 + x[3] * f.e2).normalized();
    Vector6d out;
    out << f.axis.cross(a), p + a * a.dot(c.data_tip - p);
    return out;
  };
  Eigen::Matrix<double, 6, 5> J;
  for (int k = 0; k < 5; ++k) {
    Eigen::Matrix<double, 5, 1> d = Eigen::Matrix<double, 5, 1>::Zero();
    d[k] = 1e-6;
    J.col(k) = (eval(d) - eval(-d)) / 2e-6;
  }
  Matrix6d cov = J * f.covariance * J.transpose();
  cov.topLeftCorner<3, 3>() += (M_PI * M_PI / 3) * f.axis * f.axis.transpose();
  cov.bottomRightCorner<3, 3>() += (c.spacing_mm * c.spacing_mm / 12) * f.axis * f.axis.transpose();
  return cov;
}

}  // namespace

ThinProfile thin_profile(const PointCloud& ref, const ThinSettings& s) {
  ThinProfile p;
  double zmin = INFINITY, zmax = -INFINITY;
  for (const auto& q : ref.points)
    if (q.allFinite()) zmin = std::min(zmin, double(q.z())), zmax = std::max(zmax, double(q.z()));
  // Circle through the cross-section (algebraic fit x^2 + y^2 + D x + E y + F = 0) of the side
  // points away from the ends: a view-dependent reference holds only the side the sensor sees,
  // so neither the centroid nor the mean distance from it would be the axis and the radius.
  Eigen::MatrixXd A(ref.points.size(), 3);
  Eigen::VectorXd b(ref.points.size());
  Eigen::Index n = 0;
  for (const auto& q : ref.points)
    if (q.allFinite() && q.z() > zmin + 0.1 * (zmax - zmin) && q.z() < zmax - 0.1 * (zmax - zmin)) {
      A.row(n) << q.x(), q.y(), 1;
      b[n++] = -(q.x() * q.x() + q.y() * q.y());
    }
  if (n < 10) return p;
  const Eigen::Vector3d x = A.topRows(n).colPivHouseholderQr().solve(b.head(n));
  const Eigen::Vector2d c(-x[0] / 2, -x[1] / 2);
  const double r2 = c.squaredNorm() - x[2];
  if (!(r2 > 0)) return p;
  p.radius_mm = std::sqrt(r2), p.length_mm = zmax - zmin;
  p.tip = Eigen::Vector3d(c.x(), c.y(), zmax);
  p.thin = 2 * p.radius_mm <= s.max_diameter_mm && p.length_mm >= s.min_aspect * 2 * p.radius_mm;
  return p;
}

bool uses_thin_detector(const PointCloud& ref, const RegistrationSettings& s) {
  if (s.thin.mode != ThinMode::Auto) return s.thin.mode == ThinMode::On;
  return thin_profile(ref, s.thin).thin;
}

namespace {

// The scan points near the axis of the prior-placed reference (all of them without a prior).
PointCloud near_prior_axis(const PointCloud& scan, const ThinProfile& prof,
                           const Eigen::Vector3d& a0, const RegistrationSettings& s) {
  const ThinSettings& t = s.thin;
  // No mixed-pixel filter here: a profile often returns one lone point off the thread, which
  // that filter takes for a mixed pixel; the cylinder fit's robust loss handles real ones.
  // Candidate points: near the axis of the prior-placed reference (all of them without a prior).
  PointCloud near;
  for (const auto& p : scan.points) {
    if (!p.allFinite()) continue;
    if (s.prior) {
      const Eigen::Vector3d tip = *s.prior * prof.tip, base = tip - a0 * prof.length_mm;
      if (segment_distance(p.cast<double>(), base, tip) > t.search_radius_mm) continue;
    }
    near.points.push_back(p);
  }
  if (near.points.size() < size_t(t.min_points))
    throw Error("scan has no usable points near the thin part's prior (" +
                std::to_string(near.points.size()) + ")");
  near.width = int(near.points.size());
  return near;
}

// The pose of the candidate chosen: z along the fitted axis, the spin about it kept from the
// prior (unobservable); status ambiguous.
void thin_pose(const Candidate& c, const Eigen::Matrix3d& R0, const ThinProfile& prof,
               RegistrationResult& r) {
  Eigen::Matrix3d R;
  R.col(2) = c.fit.axis;
  Eigen::Vector3d x = R0.col(0) - c.fit.axis * c.fit.axis.dot(R0.col(0));
  if (x.norm() < 1e-6) x = c.fit.axis.unitOrthogonal();
  R.col(0) = x.normalized();
  R.col(1) = R.col(2).cross(R.col(0));
  r.T_scan_ref.linear() = R;
  r.T_scan_ref.translation() = c.tip - R * prof.tip;
  r.status = Status::Ambiguous;
  r.unobservable = 1;
  r.weakest_direction << c.fit.axis, Eigen::Vector3d::Zero();
  r.hessian_centre = c.tip, r.hessian_radius_mm = 1;  // the spin about the axis through the tip
  r.fitness_mm2 = c.fit.rmse_mm * c.fit.rmse_mm, r.inlier_rmse_mm = c.fit.rmse_mm;
  r.overlap = std::min(1.0, c.length_mm / prof.length_mm);
  r.covariance = tip_covariance(c);
  std::ostringstream why;
  why << "thin part: rotation about its own axis unobservable; cylinder r " << c.fit.radius_mm * 1e3
      << " um seen over " << c.length_mm << " mm, tip " << c.distance_mm
      << " mm from the prior, axial sampling " << c.spacing_mm * 1e3 << " um";
  r.reason = why.str();
  r.log.push_back(r.reason);
}

}  // namespace

RegistrationResult detect_thin_part(const PointCloud& scan, const PointCloud& ref,
                                    const RegistrationSettings& s) {
  const auto t0 = std::chrono::steady_clock::now();
  const ThinSettings& t = s.thin;
  const ThinProfile prof = thin_profile(ref, t);
  if (prof.radius_mm <= 0) throw Error("reference cloud has no usable points");
  if (!s.prior && !s.q0)
    throw Error("a thin part is detected along its prior axis: give a prior pose or orientation");
  const Eigen::Matrix3d R0 = s.prior ? s.prior->rotation() : s.q0->toRotationMatrix();
  const Eigen::Vector3d a0 = R0.col(2);
  const PointCloud near = near_prior_axis(scan, prof, a0, s);
  const PclCloud::Ptr all = to_pcl(near);
  const std::vector<int> lin = linear_points(*all, t);
  const PclCloud::Ptr cloud(new PclCloud);
  for (int i : lin) cloud->push_back(all->at(i));
  std::vector<pcl::PointIndices> found;
  if (!cloud->empty()) {
    Tree::Ptr tree(new Tree);
    tree->setInputCloud(cloud);
    pcl::EuclideanClusterExtraction<PointT> ec;
    ec.setClusterTolerance(t.cluster_tolerance_mm);
    ec.setMinClusterSize(t.min_points);
    ec.setMaxClusterSize(int(cloud->size()));
    ec.setSearchMethod(tree);
    ec.setInputCloud(cloud);
    ec.extract(found);
  }

  RegistrationResult r;
  r.voxel_mm = s.pre.voxel_mm;
  std::vector<Candidate> ok;
  std::map<std::string, int> rejected;
  for (const auto& idx : found) {
    std::vector<Eigen::Vector3d> pts;
    for (int i : idx.indices) pts.push_back(cloud->at(i).getVector3fMap().cast<double>());
    Candidate c;
    const std::string why = assess(pts, near.points, prof, a0, s, c);
    if (!why.empty()) {
      ++rejected[why.substr(0, why.find_first_of("0123456789"))];
      continue;
    }
    c.distance_mm = s.prior ? (c.tip - *s.prior * prof.tip).norm() : 0.0;
    ok.push_back(c);
  }
  r.attempts = int(found.size());
  std::ostringstream summary;
  summary << lin.size() << " of " << all->size() << " points near the prior on lines, "
          << found.size() << " clusters, " << ok.size() << " thin along its axis";
  for (const auto& [why, n] : rejected) summary << "; " << n << " " << why;
  r.log.push_back("thin-part detector: " + summary.str());
  r.timings_s["thin"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (ok.empty() || (!s.prior && ok.size() > 1)) {
    r.status = Status::Failed;
    r.reason = ok.empty()
                   ? "no thin part found (" + summary.str() + ")"
                   : std::to_string(ok.size()) + " thin candidates and no prior position to choose";
    return r;
  }
  thin_pose(*std::min_element(ok.begin(), ok.end(),
                              [](const Candidate& x, const Candidate& y) {
                                return x.distance_mm < y.distance_mm;
                              }),
            R0, prof, r);
  return r;
}

}  // namespace laserfit::registration
