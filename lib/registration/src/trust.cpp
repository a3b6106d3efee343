// Fit statistics and the trust decision: low overlap or high RMSE -> failed; a (near) singular
// point-to-plane Hessian -> ambiguous along its weakest direction (e.g. rotation about a round
// peg's axis) instead of an arbitrary angle; otherwise ok, with covariance sigma^2 H^-1.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "laserfit/core/error.hpp"
#include "stages.hpp"

namespace laserfit::registration {

std::vector<Match> match(const PclCloud& scan, const Tree& ref_tree, const Pose& T,
                         const Matcher& m) {
  std::vector<Match> out;
  out.reserve(scan.size());
  if (!T.matrix().allFinite()) return out;
  const Pose to_ref = T.inverse();
  const Eigen::Matrix3d R = T.rotation();
  std::vector<Eigen::Vector3f> queries(scan.size());
  for (size_t i = 0; i < scan.size(); ++i)
    queries[i] = (to_ref * scan[i].getVector3fMap().cast<double>()).cast<float>();
  std::vector<int> idx;
  std::vector<float> d2;
  ref_tree.nearest_batch(queries, idx, d2, float(m.gate * m.gate));
  const auto& ref = *ref_tree.getInputCloud();
  for (size_t i = 0; i < scan.size(); ++i) {
    if (idx[i] < 0 || d2[i] > m.gate * m.gate) continue;
    const auto& pt = scan[i];
    const auto& r = ref[idx[i]];
    const Eigen::Vector3d n = R * r.getNormalVector3fMap().cast<double>();
    if (m.oriented && pt.getNormalVector3fMap().cast<double>().dot(n) < 0) continue;
    out.push_back({T * r.getVector3fMap().cast<double>(), pt.getVector3fMap().cast<double>(), n});
  }
  return out;
}

Fit evaluate(const PclCloud& scan, const Tree& ref_tree, const Pose& T, const Matcher& m) {
  Fit f;
  f.fitness_mm2 = f.rmse_mm = std::numeric_limits<double>::infinity();
  const auto M = match(scan, ref_tree, T, m);
  double sum = 0;
  for (const auto& x : M) sum += std::pow(x.n.dot(x.p - x.q), 2);
  f.inliers = M.size();
  f.overlap = scan.empty() ? 0 : double(f.inliers) / scan.size();
  if (f.inliers) f.fitness_mm2 = sum / f.inliers, f.rmse_mm = std::sqrt(f.fitness_mm2);
  return f;
}

PlaneSystem plane_system(const PclCloud& scan, const Tree& ref_tree, const Pose& T,
                         const Matcher& m) {
  // Point-to-plane Hessian over the matched scan points, with the reference's (CAD) normals,
  // about the matched points' centroid (so rotation and translation decouple); rotations scaled
  // by the RMS radius L to make the six directions comparable. All in the scan frame.
  PlaneSystem sys;
  auto M = match(scan, ref_tree, T, m);
  sys.n = M.size();
  Eigen::Vector3d& c = sys.c;
  for (const auto& x : M) c += x.q, sys.residual2 += std::pow(x.n.dot(x.q - x.p), 2);
  c /= std::max<size_t>(sys.n, 1);
  double L2 = 0;
  for (const auto& x : M) L2 += (x.q - c).squaredNorm();
  sys.L = std::max(std::sqrt(L2 / std::max<size_t>(sys.n, 1)), 1e-9);
  for (const auto& x : M) {
    Vector6d J;
    J << (x.q - c).cross(x.n) / sys.L, x.n;
    sys.H += J * J.transpose();
  }
  sys.matches = std::move(M);
  return sys;
}

double robust_sigma(const std::vector<Match>& M) {
  if (M.empty()) return std::numeric_limits<double>::infinity();
  std::vector<double> a(M.size());
  for (size_t i = 0; i < M.size(); ++i) a[i] = std::abs(M[i].n.dot(M[i].q - M[i].p));
  return robust_sigma_of(a);
}

double robust_sigma_of(std::vector<double>& a) {
  auto mid = a.begin() + long(a.size() / 2);
  std::nth_element(a.begin(), mid, a.end());
  return 1.4826 * *mid;  // the median absolute residual of a normal distribution is 0.6745 sigma
}

namespace {
// A (scaled) Hessian direction [rotation; translation] read as the DoF it mostly is.
struct Dof {
  bool rotation;
  Eigen::Vector3d axis;  // unit, scan frame
};
Dof dof_of(const Vector6d& d) {
  const bool rot = d.head<3>().norm() > d.tail<3>().norm();
  return {rot, (rot ? d.head<3>() : d.tail<3>()).normalized()};
}
bool along(const Dof& dof, const Eigen::Vector3d& axis, double tol_deg) {
  return std::abs(dof.axis.dot(axis.normalized())) > std::cos(tol_deg * M_PI / 180);
}
std::ostream& operator<<(std::ostream& o, const Dof& d) {
  return o << (d.rotation ? "rotation about" : "translation along") << " [" << d.axis.x() << ", "
           << d.axis.y() << ", " << d.axis.z() << "]";
}
bool weakest_along(const RegistrationResult& r, bool rotation, const Eigen::Vector3d& axis,
                   double tol_deg) {
  if (r.status != Status::Ambiguous || r.not_pinned) return false;  // not pinned: it names no DoF
  const Dof dof = dof_of(r.weakest_direction);
  return dof.rotation == rotation && along(dof, axis, tol_deg);
}

// The weak Hessian direction (ratio below declared_weak_ratio) that is a rotation about / a
// translation along a declared weak axis, or -1.
int declared_weak(const Eigen::SelfAdjointEigenSolver<Matrix6d>& es, const Pose& T,
                  const TrustSettings& t) {
  for (int k = 0; k < 6 && es.eigenvalues()[k] < t.declared_weak_ratio * es.eigenvalues()[5]; ++k) {
    const Dof dof = dof_of(es.eigenvectors().col(k));
    const auto& axis = dof.rotation ? t.weak_rotation : t.weak_translation;
    if (axis && along(dof, T.rotation() * *axis, 10)) return k;
  }
  return -1;
}
}  // namespace

void assess(const PclCloud& scan, const Tree& ref_tree, const Matcher& m, const TrustSettings& t,
            double voxel, RegistrationResult& r) {
  // One pass over the scan gives both the fit statistics and the normal equations.
  const PlaneSystem sys = plane_system(scan, ref_tree, r.T_scan_ref, m);
  Fit f;
  f.inliers = sys.n;
  f.overlap = scan.empty() ? 0 : double(sys.n) / scan.size();
  f.fitness_mm2 = sys.n ? sys.residual2 / sys.n : std::numeric_limits<double>::infinity();
  f.rmse_mm = std::sqrt(f.fitness_mm2);
  r.fitness_mm2 = f.fitness_mm2, r.inlier_rmse_mm = f.rmse_mm, r.overlap = f.overlap;
  r.residual_sigma_mm = robust_sigma(sys.matches);
  const Matrix6d& H = sys.H;
  const size_t n = sys.n;
  const double res2 = sys.residual2, L = sys.L;
  Eigen::SelfAdjointEigenSolver<Matrix6d> es(H);
  r.hessian_eigenvalues = es.eigenvalues() / std::max(1.0, double(n));
  r.weakest_direction = es.eigenvectors().col(0);
  r.hessian_centre = sys.c, r.hessian_radius_mm = L;
  r.flat = 0, r.unobservable = 0;  // r may have been assessed at another pose before
  r.flat_from_mm = r.flat_to_mm = 0;
  for (int k = 0; k < 6; ++k)
    r.flat += es.eigenvalues()[k] < t.ambiguity_ratio * es.eigenvalues()[5];
  const double sigma2 = n > 6 ? res2 / (n - 6) : 0.0;
  // Covariance in [rx ry rz (rad, about the reference centroid), tx ty tz (mm)]: undo the scaling.
  Vector6d inv = es.eigenvalues();
  for (int k = 0; k < 6; ++k) inv[k] = inv[k] > 1e-12 * es.eigenvalues()[5] ? 1.0 / inv[k] : 0.0;
  Matrix6d cov = sigma2 * es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
  Vector6d s;
  s << 1 / L, 1 / L, 1 / L, 1, 1, 1;
  r.covariance = s.asDiagonal() * cov * s.asDiagonal();
  // Not computed (too few matched points for its blocks): unknown, so infinite; 0 when disabled.
  r.sigma_origin_mm = r.sigma_rotation_deg =
      t.jackknife_blocks > 0 ? std::numeric_limits<double>::infinity() : 0;
  if (const auto cj = block_jackknife(sys.matches, sys.c, L, t.jackknife_blocks)) {
    r.sigma_origin_mm = origin_sigma_mm(*cj, r.T_scan_ref.translation() - sys.c);
    r.sigma_rotation_deg = top_sigma(cj->topLeftCorner<3, 3>()) * 180 / M_PI;
  }

  std::ostringstream why;
  if (f.overlap < t.min_overlap) {
    r.status = Status::Failed;
    why << "overlap " << f.overlap << " below " << t.min_overlap;
  } else if (f.rmse_mm > t.max_rmse_vox * voxel) {
    r.status = Status::Failed;
    why << "inlier RMSE " << f.rmse_mm * 1e3 << " um above " << t.max_rmse_vox * voxel * 1e3
        << " um";
  } else if (es.eigenvalues()[0] < t.ambiguity_ratio * es.eigenvalues()[5]) {
    r.status = Status::Ambiguous;
    r.unobservable = r.flat;
    why << "unobservable " << dof_of(r.weakest_direction) << " (scan frame)";
    if (r.flat > 1) why << " and " << r.flat - 1 << " more direction(s)";
  } else if (const int k = declared_weak(es, r.T_scan_ref, t); k >= 0) {
    r.status = Status::Ambiguous;
    r.weakest_direction = es.eigenvectors().col(k);
    r.unobservable = 1;
    why << "weakly observable " << dof_of(r.weakest_direction)
        << " (scan frame; declared weak, Hessian ratio "
        << es.eigenvalues()[k] / es.eigenvalues()[5] << " below " << t.declared_weak_ratio << ")";
  } else {
    r.status = Status::Ok;
  }
  r.reason = why.str();
}

std::optional<Eigen::Vector3d> named_axis(const std::string& name) {
  if (name.empty()) return std::nullopt;
  if (name != "x" && name != "y" && name != "z")
    throw Error("axis '" + name + "': must be x, y or z");
  return Eigen::Vector3d::Unit(name[0] - 'x');
}

double top_sigma(const Eigen::Matrix3d& C) {
  return C.allFinite()
             ? std::sqrt(std::max(
                   0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues()[2]))
             : std::numeric_limits<double>::infinity();
}

double origin_sigma_mm(const Matrix6d& covariance, const Eigen::Vector3d& oc) {
  // The origin moves by w x oc + t for a rotation w about the centre and a shift t.
  Eigen::Matrix3d oc_x;  // oc_x * w = oc x w
  oc_x << 0, -oc.z(), oc.y(), oc.z(), 0, -oc.x(), -oc.y(), oc.x(), 0;
  Eigen::Matrix<double, 3, 6> J;
  J << -oc_x, Eigen::Matrix3d::Identity();
  return top_sigma(J * covariance * J.transpose());
}

void check_pinned(const TrustSettings& t, RegistrationResult& r) {
  r.not_pinned = false;
  if (r.status != Status::Ok) return;
  if ((t.max_sigma_mm > 0 && r.sigma_origin_mm > t.max_sigma_mm) ||
      (t.max_sigma_deg > 0 && r.sigma_rotation_deg > t.max_sigma_deg)) {
    std::ostringstream why;
    if (!std::isfinite(r.sigma_origin_mm) && !std::isfinite(r.sigma_rotation_deg))
      why << "not pinned: the jackknife could not bound it (fewer than "
          << 20 * t.jackknife_blocks * t.jackknife_blocks
          << " matched points, or one region alone pins a direction)";
    else
      why << "not pinned: leaving out one region of the scan moves the origin by sigma "
          << r.sigma_origin_mm * 1e3 << " um (limit " << t.max_sigma_mm * 1e3
          << "), the rotation by " << r.sigma_rotation_deg << " deg (limit " << t.max_sigma_deg
          << ")";
    r.status = Status::Ambiguous;
    r.not_pinned = true;
    r.reason = why.str();
  }
}

bool weakest_is_rotation_about(const RegistrationResult& r, const Eigen::Vector3d& axis,
                               double tol_deg) {
  return weakest_along(r, true, axis, tol_deg);
}
bool weakest_is_translation_along(const RegistrationResult& r, const Eigen::Vector3d& axis,
                                  double tol_deg) {
  return weakest_along(r, false, axis, tol_deg);
}

Pose along_weakest_to(const RegistrationResult& r, const Pose& toward) {
  // The motion from r's pose to toward as a twist about the centre, in the Hessian's scaled
  // coordinates [L w; v] (w: rotation vector, v: the centre's displacement), where the
  // eigenvectors are orthonormal; its component along the weakest one is applied to r's pose.
  const double L = r.hessian_radius_mm;
  const Eigen::Vector3d& c = r.hessian_centre;
  const Pose D = toward * r.T_scan_ref.inverse();
  const Eigen::AngleAxisd turn(D.linear());
  Vector6d d;
  d << L * turn.angle() * turn.axis(), D * c - c;
  const Vector6d& e = r.weakest_direction;
  const double amount = e.squaredNorm() > 0 ? e.dot(d) / e.squaredNorm() : 0.0;
  const Eigen::Vector3d w = amount * e.head<3>() / L, v = amount * e.tail<3>();
  Pose M = Pose::Identity();
  if (w.norm() > 0) M.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  M.translation() = c + v - M.linear() * c;
  return M * r.T_scan_ref;
}

}  // namespace laserfit::registration
