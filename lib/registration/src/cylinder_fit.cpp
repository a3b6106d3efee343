// Cylinder fit for thin parts. Parameters about the guess (no gauge freedom along the axis):
// axis point c = c0 + u e1 + v e2, direction a = normalize(a0 + alpha e1 + beta e2), radius r;
// residual of a point p: |(p - c) - ((p - c) . a) a| - r. A line scanner sees a 150 um thread
// over a +-30 degree arc only (grazing incidence, camera shadow): the sagitta of that arc is
// ~10 um, so the radius is barely observable and trades off against the axis' depth; the radius
// is therefore usually held at the reference's, and the axis may be tied to a prior direction
// (a Gaussian prior of sigma axis_sigma_rad on alpha, beta), since a few points per profile
// over a millimetre or two pin the direction far worse than the gripper does.
#include <ceres/ceres.h>

#include <cmath>

#include "laserfit/registration/thin.hpp"

namespace laserfit::registration {
namespace {

struct AxisPrior {
  explicit AxisPrior(double sigma) : w(1 / sigma) {}
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = x[2] * w, r[1] = x[3] * w;
    return true;
  }
  double w;
};

struct AxisDistance {
  AxisDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& c0, const Eigen::Vector3d& a0,
               const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, double w = 1)
      : p(p), c0(c0), a0(a0), e1(e1), e2(e2), w(w) {}
  template <typename T>
  bool operator()(const T* x, const T* radius, T* r) const {
    using V = Eigen::Matrix<T, 3, 1>;
    const V c = c0.cast<T>() + x[0] * e1.cast<T>() + x[1] * e2.cast<T>();
    const V a = (a0.cast<T>() + x[2] * e1.cast<T>() + x[3] * e2.cast<T>()).normalized();
    const V d = p.cast<T>() - c;
    const V perp = d - d.dot(a) * a;
    r[0] = (sqrt(perp.squaredNorm() + T(1e-18)) - radius[0]) *
           w;  // the epsilon keeps the Jacobian finite
    return true;
  }
  Eigen::Vector3d p, c0, a0, e1, e2;
  double w;  // 1 / noise: whitened, so that the axis prior and the points weigh as they should
};

}  // namespace

CylinderFit fit_cylinder(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& point0,
                         const Eigen::Vector3d& axis0, double radius0, double robust_mm,
                         const CylinderFitOptions& o) {
  CylinderFit f;
  const Eigen::Vector3d a0 = axis0.normalized();
  f.e1 = a0.unitOrthogonal(), f.e2 = a0.cross(f.e1);
  double x[4] = {0, 0, 0, 0}, radius[1] = {radius0};
  ceres::Problem problem;
  for (const auto& p : pts)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<AxisDistance, 1, 4, 1>(
                                 new AxisDistance(p, point0, a0, f.e1, f.e2, 1 / o.noise_mm)),
                             new ceres::HuberLoss(robust_mm / o.noise_mm), x, radius);
  if (o.axis_sigma_rad > 0)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<AxisPrior, 2, 4>(new AxisPrior(o.axis_sigma_rad)), nullptr,
        x);
  if (o.fix_radius) problem.SetParameterBlockConstant(radius);
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::DENSE_QR;
  opt.max_num_iterations = 100;
  opt.num_threads = 1;  // deterministic, and the problem is tiny
  ceres::Solver::Summary sum;
  ceres::Solve(opt, &problem, &sum);
  f.converged =
      sum.termination_type == ceres::CONVERGENCE && std::isfinite(radius[0]) && radius[0] > 0;
  f.point = point0 + x[0] * f.e1 + x[1] * f.e2;
  f.axis = (a0 + x[2] * f.e1 + x[3] * f.e2).normalized();
  f.radius_mm = radius[0];
  // Inliers within three robust scales; their RMS is the fit's quality, their scatter its noise.
  f.inlier.assign(pts.size(), 0);
  double ss = 0;
  size_t n = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    double r;
    AxisDistance(pts[i], point0, a0, f.e1, f.e2)(x, radius, &r);
    if (std::abs(r) <= 3 * robust_mm) f.inlier[i] = 1, ss += r * r, ++n;
  }
  f.inlier_fraction = pts.empty() ? 0 : double(n) / double(pts.size());
  f.rmse_mm = n ? std::sqrt(ss / double(n)) : 0;
  const int dof = o.fix_radius ? 4 : 5;
  if (!f.converged || n <= size_t(dof)) return f;
  ceres::Covariance::Options copt;
  copt.algorithm_type = ceres::DENSE_SVD;  // a nearly flat candidate must not abort the estimate
  copt.null_space_rank = -1;
  ceres::Covariance cov(copt);
  std::vector<std::pair<const double*, const double*>> blocks = {{x, x}};
  if (!o.fix_radius) blocks.push_back({x, radius}), blocks.push_back({radius, radius});
  if (cov.Compute(blocks, &problem)) {
    Eigen::Matrix<double, 4, 4, Eigen::RowMajor> c;
    cov.GetCovarianceBlock(x, x, c.data());
    f.covariance.topLeftCorner<4, 4>() = c;
    if (!o.fix_radius) {
      Eigen::Matrix<double, 4, 1> cr;
      cov.GetCovarianceBlock(x, radius, cr.data());
      f.covariance.block<4, 1>(0, 4) = cr, f.covariance.block<1, 4>(4, 0) = cr.transpose();
      cov.GetCovarianceBlock(radius, radius, &f.covariance(4, 4));
    }
    // Whitened with the nominal noise; inflated when the points scatter more than that.
    f.covariance *= std::max(1.0, ss / double(n - dof) / (o.noise_mm * o.noise_mm));
  }
  return f;
}

}  // namespace laserfit::registration
