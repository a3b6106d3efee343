// Robust point-to-plane refinement on SE(3) with Ceres: for every scan point q and its nearest
// reference point p (dense CAD samples), residual r = n . (T p - q) with the reference's exact
// normal n rotated into the scan frame; robust loss (Huber / Cauchy / Tukey); analytic Jacobian
// of the left perturbation T <- exp([w, v]) T:  d r / d[w, v] = [(Tp x n)^T, n^T].
// Multi-scale: the correspondence gate shrinks 4x -> 2x -> 1x as the pose converges.
#include <ceres/ceres.h>

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

ceres::LossFunction* make_loss(const std::string& name, double scale) {
  if (name == "huber") return new ceres::HuberLoss(scale);
  if (name == "cauchy") return new ceres::CauchyLoss(scale);
  if (name == "tukey") return new ceres::TukeyLoss(scale);
  if (name == "none") return nullptr;
  throw Error("unknown robust loss '" + name + "' (huber, cauchy, tukey, none)");
}

}  // namespace

RefineOutput refine_ceres(const RefineInput& in) {
  RefineOutput out;
  out.T = in.init;
  std::vector<int> idx(1);
  std::vector<float> d2(1);
  for (const double scale : {4.0, 2.0, 1.0}) {
    const double gate = scale * in.s.max_correspondence_vox * in.voxel;
    for (int it = 0; it < in.s.max_iterations; ++it, ++out.iterations) {
      ceres::Problem::Options po;
      po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(po);
      std::unique_ptr<ceres::LossFunction> loss(make_loss(in.s.robust_loss, in.s.robust_scale_vox * in.voxel));
      double delta[6] = {0, 0, 0, 0, 0, 0};
      size_t used = 0;
      const Pose to_ref = out.T.inverse();
      const Eigen::Matrix3d R = out.T.rotation();
      for (const auto& pt : *in.scan) {
        const Eigen::Vector3d q = pt.getVector3fMap().cast<double>();
        PointT query;
        query.getVector3fMap() = (to_ref * q).cast<float>();
        if (in.ref_tree->nearestKSearch(query, 1, idx, d2) < 1 || d2[0] > gate * gate) continue;
        const auto& m = (*in.ref)[idx[0]];
        problem.AddResidualBlock(new PointToPlane(out.T * m.getVector3fMap().cast<double>(), q,
                                                  R * m.getNormalVector3fMap().cast<double>()),
                                 loss.get(), delta);
        ++used;
      }
      if (used < 6) break;  // cannot constrain six degrees of freedom
      ceres::Solver::Options so;
      so.linear_solver_type = ceres::DENSE_QR;
      so.max_num_iterations = 10;
      so.num_threads = 1;  // deterministic
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
      const Eigen::Map<const Eigen::Vector3d> w(delta), v(delta + 3);
      Pose step = Pose::Identity();
      if (w.norm() > 0) step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
      step.translation() = v;
      out.T = step * out.T;
      // Largest displacement of a point 10 voxels out: the update is negligible below this.
      if (v.norm() + w.norm() * 10 * in.voxel < in.s.convergence_mm) break;
    }
  }
  return out;
}

}  // namespace laserfit::registration
