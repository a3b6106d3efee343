// Block jackknife of the point-to-plane solution. sigma^2 H^-1 assumes independent residuals; a
// scanner's are not: an edge biased by mixed pixels, or a lone hole outline that alone pins the
// in-plane rotation, shifts many neighbouring residuals together. Splitting the matched points
// into spatial blocks and re-solving the normal equations with each block left out (one
// Gauss-Newton step from the final pose) measures how much the pose leans on any one region;
// the spread of those solutions is the jackknife covariance (Efron & Stein; Kunsch 1989 for
// blocks of dependent data), which counts correlated residuals within a block.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>

#include "stages.hpp"

namespace laserfit::registration {

namespace {
// Splits idx (sorted in place by key) into `parts` runs of nearly equal length.
std::vector<std::vector<int>> quantile_split(std::vector<int> idx, const std::vector<double>& key,
                                             int parts) {
  std::sort(idx.begin(), idx.end(),
            [&](int a, int b) { return key[a] < key[b] || (key[a] == key[b] && a < b); });
  std::vector<std::vector<int>> out(parts);
  for (size_t i = 0; i < idx.size(); ++i) out[i * parts / idx.size()].push_back(idx[i]);
  return out;
}
}  // namespace

std::optional<Matrix6d> block_jackknife(const std::vector<Match>& M, const Eigen::Vector3d& c,
                                        double L, int per_axis) {
  const int K = per_axis * per_axis;
  if (per_axis < 2 || M.size() < size_t(20 * K)) return std::nullopt;
  // Blocks: quantiles along the matched points' two principal axes (equal counts; a grid of
  // equal widths would leave blocks empty on an L-shaped view).
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& x : M) C += (x.q - c) * (x.q - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(C);
  const Eigen::Vector3d e1 = pca.eigenvectors().col(2), e2 = pca.eigenvectors().col(1);
  std::vector<double> k1(M.size()), k2(M.size());
  for (size_t i = 0; i < M.size(); ++i) k1[i] = e1.dot(M[i].q - c), k2[i] = e2.dot(M[i].q - c);
  std::vector<int> all(M.size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<Matrix6d> Hb(K, Matrix6d::Zero());
  std::vector<Vector6d> gb(K, Vector6d::Zero());
  int b = 0;
  for (const auto& strip : quantile_split(all, k1, per_axis))
    for (const auto& block : quantile_split(strip, k2, per_axis)) {
      for (int i : block) {
        const auto& x = M[i];
        Vector6d J;
        J << (x.q - c).cross(x.n) / L, x.n;
        Hb[b] += J * J.transpose();
        gb[b] += J * x.n.dot(x.q - x.p);
      }
      ++b;
    }
  const Matrix6d H = std::accumulate(Hb.begin(), Hb.end(), Matrix6d(Matrix6d::Zero()));
  const Vector6d g = std::accumulate(gb.begin(), gb.end(), Vector6d(Vector6d::Zero()));
  // Scaled so the six directions are comparable; a block whose removal leaves a DoF free gives a
  // huge (or non-finite) step, which is the point: that block alone pins it.
  std::vector<Vector6d> d(K);
  Vector6d mean = Vector6d::Zero();
  for (int k = 0; k < K; ++k) {
    d[k] = (H - Hb[k]).ldlt().solve(g - gb[k]);
    if (!d[k].allFinite()) return Matrix6d::Constant(std::numeric_limits<double>::infinity());
    mean += d[k] / K;
  }
  Matrix6d cov = Matrix6d::Zero();
  for (const auto& dk : d) cov += (dk - mean) * (dk - mean).transpose();
  cov *= double(K - 1) / K;
  Vector6d s;
  s << 1 / L, 1 / L, 1 / L, 1, 1, 1;  // back to [rad, mm]
  return s.asDiagonal() * cov * s.asDiagonal();
}

}  // namespace laserfit::registration
