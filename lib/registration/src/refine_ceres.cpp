// Robust point-to-plane refinement on SE(3) with Ceres: for every scan point q and its nearest
// reference point p (dense CAD samples), residual r = n . (T p - q) with the reference's exact
// normal n rotated into the scan frame; robust loss (Huber / Cauchy / Tukey); analytic Jacobian
// of the left perturbation T <- exp([w, v]) T:  d r / d[w, v] = [(Tp x n)^T, n^T].
// Multi-scale: the correspondence gate halves from max(4x, initial_gate_mm) down to 1x as the pose
// converges. Each iteration re-matches and solves the robust linearised problem: by iteratively
// reweighted Gauss-Newton (a 6x6 solve) until the pose settles, then at the finest gate by Ceres
// until its step is negligible too, so the pose returned is the minimum Ceres finds.
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

  Vector6d jacobian() const { return (Vector6d() << p_.cross(n_), n_).finished(); }
  double residual0() const { return n_.dot(p_ - q_); }

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

// The problem of one iteration: the matches about their centroid c (rotations taken there),
// with the damping's weight and the RMS radius L that scales it.
struct Linearised {
  std::deque<PointToPlane> rows;  // not moved as it grows: Ceres holds their addresses
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double damping = 0, L = 1;
};

Linearised linearise(const std::vector<Match>& M) {
  Linearised lin;
  for (const auto& x : M) lin.c += x.q;
  lin.c /= double(M.size());
  double L2 = 0;
  for (const auto& x : M) {
    lin.rows.emplace_back(x.p - lin.c, x.q - lin.c, x.n);
    L2 += (x.q - lin.c).squaredNorm();
  }
  lin.damping = 1e-3 * std::sqrt(double(M.size())), lin.L = std::sqrt(L2 / double(M.size()));
  return lin;
}

// Ceres's Levenberg-Marquardt on the robust linearised problem: the step the method is named for.
Vector6d solve_ceres(Linearised& lin, ceres::LossFunction* loss, ceres::Context* context) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.disable_all_safety_checks = true;  // one parameter block, every residual built right here
  po.context = context;
  ceres::Problem problem(po);
  Vector6d delta = Vector6d::Zero();
  for (auto& row : lin.rows) problem.AddResidualBlock(&row, loss, delta.data());
  Damping damping(lin.damping, lin.L);
  problem.AddResidualBlock(&damping, nullptr, delta.data());
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 10;
  so.num_threads = 1;  // deterministic
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return delta;
}

// Largest displacement of a point reach_mm from c under the step: the update's size in mm.
double displacement(const Vector6d& delta, double reach_mm) {
  return delta.tail<3>().norm() + delta.head<3>().norm() * reach_mm;
}

// The robust minimum by iteratively reweighted least squares: the loss's weights rho'(r^2) at the
// current step, then the 6x6 normal equations with the damping (small_gicp's robust Gauss-Newton).
// Each sweep costs one pass over the matches instead of a Ceres evaluation per residual.
Vector6d solve_irls(const Linearised& lin, const ceres::LossFunction* loss, double reach_mm,
                    double tolerance_mm) {
  Vector6d delta = Vector6d::Zero();
  Matrix6d D2 = Matrix6d::Zero();
  for (int k = 0; k < 6; ++k) D2(k, k) = std::pow(lin.damping * (k < 3 ? lin.L : 1.0), 2);
  for (int sweep = 0; sweep < 10; ++sweep) {
    Matrix6d H = D2;
    Vector6d g = Vector6d::Zero();
    for (const auto& row : lin.rows) {
      const Vector6d J = row.jacobian();
      const double r0 = row.residual0(), r = r0 + J.dot(delta);
      double rho[3] = {0, 1, 0};
      if (loss) loss->Evaluate(r * r, rho);
      H.selfadjointView<Eigen::Lower>().rankUpdate(J, rho[1]);
      g += rho[1] * r0 * J;
    }
    const Vector6d next = H.selfadjointView<Eigen::Lower>().ldlt().solve(-g);
    const double moved = displacement(next - delta, reach_mm);
    delta = next;
    if (!loss || moved < tolerance_mm) break;
  }
  return delta;
}

// x -> exp(w) (x - c) + c + v, applied to the pose (the left perturbation about c).
Pose step_about(const Vector6d& delta, const Eigen::Vector3d& c) {
  const Eigen::Vector3d w = delta.head<3>(), v = delta.tail<3>();
  Pose step = Pose::Identity();
  if (w.norm() > 0) step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  step.translation() = c - step.linear() * c + v;
  return step;
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
  std::unique_ptr<ceres::Context> context(ceres::Context::Create());  // one for every solve
  const double reach = 10 * in.voxel;  // the update is negligible when points this far out stay
  for (const double scale : scales) {
    const double gate = scale * fine;
    std::unique_ptr<ceres::LossFunction> loss(
        make_loss(in.s.robust_loss, in.s.robust_scale_vox * scale * in.voxel));
    // Robust Gauss-Newton until the pose settles; at the finest gate Ceres then solves from
    // there until its step is negligible too: the pose returned is Ceres's minimum.
    bool polish = false;
    for (int it = 0; it < in.s.max_iterations; ++it, ++out.iterations) {
      const auto M = match(*in.scan, *in.ref_tree, out.T, {gate, in.oriented});
      if (M.size() < 6) break;  // cannot constrain six degrees of freedom
      Linearised lin = linearise(M);
      const bool ceres_step = polish || (scale == 1.0 && it + 1 == in.s.max_iterations);
      const Vector6d delta = ceres_step
                                 ? solve_ceres(lin, loss.get(), context.get())
                                 : solve_irls(lin, loss.get(), reach, 1e-3 * in.s.convergence_mm);
      out.T = step_about(delta, lin.c) * out.T;
      if (displacement(delta, reach) >= in.s.convergence_mm) continue;
      if (scale > 1.0 || ceres_step) break;
      polish = true;
    }
  }
  return out;
}

}  // namespace laserfit::registration
