// Cylinder fit for thin parts. Parameters about the guess (no gauge freedom along the axis):
// axis point c = c0 + u e1 + v e2, direction a = normalize(a0 + alpha e1 + beta e2), radius r;
// residual of a point p: |(p - c) - ((p - c) . a) a| - r. Seen from one side the arc still fixes
// the radius: its sagitta is r itself for a half circle, ~40x the sensor's depth noise.
#include <ceres/ceres.h>

#include <cmath>

#include "laserfit/registration/thin.hpp"

namespace laserfit::registration {
namespace {

struct AxisDistance {
  AxisDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& c0, const Eigen::Vector3d& a0,
               const Eigen::Vector3d& e1, const Eigen::Vector3d& e2)
      : p(p), c0(c0), a0(a0), e1(e1), e2(e2) {}
  template <typename T>
  bool operator()(const T* x, T* r) const {
    using V = Eigen::Matrix<T, 3, 1>;
    const V c = c0.cast<T>() + x[0] * e1.cast<T>() + x[1] * e2.cast<T>();
    const V a = (a0.cast<T>() + x[2] * e1.cast<T>() + x[3] * e2.cast<T>()).normalized();
    const V d = p.cast<T>() - c;
    const V perp = d - d.dot(a) * a;
    r[0] = sqrt(perp.squaredNorm() + T(1e-18)) - x[4];  // the epsilon keeps the Jacobian finite
    return true;
  }
  Eigen::Vector3d p, c0, a0, e1, e2;
};

}  // namespace

CylinderFit fit_cylinder(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& point0,
                         const Eigen::Vector3d& axis0, double radius0, double robust_mm) {
  CylinderFit f;
  const Eigen::Vector3d a0 = axis0.normalized();
  f.e1 = a0.unitOrthogonal(), f.e2 = a0.cross(f.e1);
  double x[5] = {0, 0, 0, 0, radius0};
  ceres::Problem problem;
  for (const auto& p : pts)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<AxisDistance, 1, 5>(new AxisDistance(p, point0, a0, f.e1, f.e2)),
                             new ceres::HuberLoss(robust_mm), x);
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::DENSE_QR;
  opt.max_num_iterations = 100;
  opt.num_threads = 1;  // deterministic, and the problem is tiny
  ceres::Solver::Summary sum;
  ceres::Solve(opt, &problem, &sum);
  f.converged = sum.termination_type == ceres::CONVERGENCE && std::isfinite(x[4]) && x[4] > 0;
  f.point = point0 + x[0] * f.e1 + x[1] * f.e2;
  f.axis = (a0 + x[2] * f.e1 + x[3] * f.e2).normalized();
  f.radius_mm = x[4];
  // Inliers within three robust scales; their RMS is the fit's quality, their scatter its noise.
  f.inlier.assign(pts.size(), 0);
  double ss = 0;
  size_t n = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    double r;
    const double* params[] = {x};
    AxisDistance(pts[i], point0, a0, f.e1, f.e2)(params[0], &r);
    if (std::abs(r) <= 3 * robust_mm) f.inlier[i] = 1, ss += r * r, ++n;
  }
  f.inlier_fraction = pts.empty() ? 0 : double(n) / double(pts.size());
  f.rmse_mm = n ? std::sqrt(ss / double(n)) : 0;
  if (!f.converged || n <= 5) return f;
  ceres::Covariance::Options copt;
  copt.algorithm_type = ceres::DENSE_SVD;  // a nearly flat candidate must not abort the estimate
  copt.null_space_rank = -1;
  ceres::Covariance cov(copt);
  std::vector<std::pair<const double*, const double*>> blocks = {{x, x}};
  if (cov.Compute(blocks, &problem)) {
    Eigen::Matrix<double, 5, 5, Eigen::RowMajor> c;
    cov.GetCovarianceBlock(x, x, c.data());
    f.covariance = c * (ss / double(n - 5));  // Ceres assumes unit residual variance
  }
  return f;
}

}  // namespace laserfit::registration
