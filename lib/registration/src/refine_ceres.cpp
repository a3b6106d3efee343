// Robust point-to-plane refinement on SE(3) with Ceres: for every scan point q and its nearest
// reference point p (dense CAD samples), residual r = n . (T p - q) with the reference's exact
// normal n rotated into the scan frame; robust loss (Huber / Cauchy / Tukey); analytic Jacobian
// of the left perturbation T <- exp([w, v]) T:  d r / d[w, v] = [(Tp x n)^T, n^T].
// Multi-scale: the correspondence gate halves from max(4x, initial_gate_mm) down to 1x as the pose
// converges.
// The perturbation is taken about the matched points' centroid c, not the scan origin (which can
// be half a metre away in the robot base frame): there a small rotation is also a large
// translation, the two columns of the Jacobian are badly scaled, and a linearised step along a
// weakly observed direction overshoots far outside the region where the linearisation holds.
#include <ceres/ceres.h>

#include <deque>

#include "laserfit/core/error.hpp"
#include "stages.hpp"

namespace laserfit::registration {
namespace {

class PointToPlane final : public ceres::SizedCostFunction<1, 6> {
 public:
  PointToPlane(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& n)
      : p_(p), q_(q), n_(n) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    const Eigen::Map<const Eigen::Vector3d> w(x[0]), v(x[0] + 3);
    r[0] = n_.dot(p_ + w.cross(p_) + v - q_);  // linearised about the current pose
    if (J && J[0]) {
      const Eigen::Vector3d jw = p_.cross(n_);
      for (int k = 0; k < 3; ++k) J[0][k] = jw[k], J[0][3 + k] = n_[k];
    }
    return true;
  }

 private:
  Eigen::Vector3d p_, q_, n_;
};

// Damping of the update (Tikhonov): w_rot * L * w and w_trans * v as extra residuals. Tiny next to
// the data along observed directions, it keeps the step finite along unobserved ones (the spin
// of a thread about its own axis), where the least-squares step is otherwise arbitrary.
class Damping final : public ceres::SizedCostFunction<6, 6> {
 public:
  Damping(double weight, double L) : w_(weight), L_(L) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    for (int k = 0; k < 6; ++k) r[k] = w_ * (k < 3 ? L_ : 1.0) * x[0][k];
    if (J && J[0]) {
      for (int k = 0; k < 36; ++k) J[0][k] = 0;
      for (int k = 0; k < 6; ++k) J[0][k * 6 + k] = w_ * (k < 3 ? L_ : 1.0);
    }
    return true;
  }

 private:
  double w_, L_;
};

ceres::LossFunction* make_loss(RobustLoss loss, double scale) {
  switch (loss) {
    case RobustLoss::Huber:
      return new ceres::HuberLoss(scale);
    case RobustLoss::Cauchy:
      return new ceres::CauchyLoss(scale);
    case RobustLoss::Tukey:
      return new ceres::TukeyLoss(scale);
    case RobustLoss::None:
      break;
  }
  return nullptr;
}

}  // namespace

RefineOutput refine_ceres(const RefineInput& in) {
  RefineOutput out;
  out.T = in.init;
  const double fine = in.s.max_correspondence_vox * in.voxel;
  std::vector<double> scales;  // coarse to fine, halving, from 4x the gate or the initial gate
  for (double sc = std::max(4.0, in.s.initial_gate_mm / fine); sc > 1.0; sc /= 2)
    scales.push_back(sc);
  scales.push_back(1.0);
  // The problem owns none of its pieces: the residuals live in one deque (not one allocation
  // each), and one context serves every solve of this refinement.
  std::unique_ptr<ceres::Context> context(ceres::Context::Create());
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.disable_all_safety_checks = true;  // one parameter block, every residual built right here
  po.context = context.get();
  std::deque<PointToPlane> residuals;  // not moved as it grows: Ceres holds their addresses
  for (const double scale : scales) {
    const double gate = scale * fine;
    for (int it = 0; it < in.s.max_iterations; ++it, ++out.iterations) {
      ceres::Problem problem(po);
      std::unique_ptr<ceres::LossFunction> loss(
          make_loss(in.s.robust_loss, in.s.robust_scale_vox * scale * in.voxel));
      double delta[6] = {0, 0, 0, 0, 0, 0};
      const auto M = match(*in.scan, *in.ref_tree, out.T, {gate, in.oriented});
      if (M.size() < 6) break;  // cannot constrain six degrees of freedom
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (const auto& x : M) c += x.q;
      c /= double(M.size());
      double L2 = 0;
      residuals.clear();
      for (const auto& x : M) {
        residuals.emplace_back(x.p - c, x.q - c, x.n);
        problem.AddResidualBlock(&residuals.back(), loss.get(), delta);
        L2 += (x.q - c).squaredNorm();
      }
      Damping damping(1e-3 * std::sqrt(double(M.size())), std::sqrt(L2 / double(M.size())));
      problem.AddResidualBlock(&damping, nullptr, delta);
      ceres::Solver::Options so;
      so.linear_solver_type = ceres::DENSE_QR;
      so.max_num_iterations = 10;
      so.num_threads = 1;  // deterministic
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
      const Eigen::Map<const Eigen::Vector3d> w(delta), v(delta + 3);
      Pose step = Pose::Identity();  // x -> exp(w) (x - c) + c + v
      if (w.norm() > 0)
        step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
      step.translation() = c - step.linear() * c + v;
      out.T = step * out.T;
      // Largest displacement of a point 10 voxels out: the update is negligible below this.
      if (v.norm() + w.norm() * 10 * in.voxel < in.s.convergence_mm) break;
    }
  }
  return out;
}

}  // namespace laserfit::registration
