// RANSAC on FPFH correspondences with the orientation prior inside the loop. The paper's
// Algorithm 1 gates the *result* of RANSAC against q0 (line 5) and repeats RANSAC when it is
// rejected; for box-like parts (a USB shell) FPFH cannot tell a face from its 180-degree twin, so
// most whole RANSAC runs end on a flipped pose and are thrown away. Testing d_phi(q, q0) < rho_rot
// on every hypothesis, before its inliers are counted, keeps the same rule but spends the budget
// on plausible poses only. Otherwise as Buch et al. 2013: three correspondences sampled among
// each scan feature's k nearest reference features, pre-rejected when their edge lengths differ,
// pose by least squares (Umeyama), scored by the inlier count on the coarse grid.
#include <pcl/kdtree/kdtree_flann.h>

#include <Eigen/Geometry>

#include "laserfit/core/rng.hpp"
#include "stages.hpp"

namespace laserfit::registration {

bool coarse_align_gated(const PclCloud::Ptr& ref, const Features::Ptr& ref_f,
                        const PclCloud::Ptr& scan, const Features::Ptr& scan_f,
                        const CoarseSettings& s, double voxel, uint64_t seed,
                        const std::optional<Eigen::Quaterniond>& q0, double rho_rot_deg, Pose& T) {
  if (scan->size() < 3 || ref->size() < 3) return false;
  // k nearest reference features of every scan feature (FLANN, exact kd-tree search).
  pcl::KdTreeFLANN<pcl::FPFHSignature33> ftree;
  ftree.setInputCloud(ref_f);
  const int k = std::max(1, s.correspondence_randomness);
  std::vector<std::vector<int>> cand(scan->size());
  std::vector<int> idx(k);
  std::vector<float> d2(k);
  for (size_t i = 0; i < scan->size(); ++i)
    if (std::isfinite((*scan_f)[i].histogram[0]) &&
        ftree.nearestKSearch((*scan_f)[i], k, idx, d2) > 0)
      cand[i] = idx;
  Tree rtree;
  rtree.setInputCloud(ref);
  const double max_d = s.max_correspondence_vox * voxel;
  const double cos_gate = std::cos(rho_rot_deg * M_PI / 360);  // |<q, q0>| >= cos(rho / 2)
  Mt19937_64 g = block_rng(seed, 0x52414E53, 0);
  size_t best_inliers = 0;
  std::vector<int> nn(1);
  std::vector<float> nd(1);
  for (int it = 0; it < s.ransac_iterations; ++it) {
    int si[3], ri[3];
    bool ok = true;
    for (int j = 0; j < 3 && ok; ++j) {
      si[j] = int(uniform01(g) * scan->size());
      const auto& c = cand[si[j]];
      ok = !c.empty();
      if (ok) ri[j] = c[size_t(uniform01(g) * c.size())];
    }
    if (!ok) continue;
    // Pre-rejection: the triangle's edges must have similar lengths in both clouds.
    for (int a = 0; a < 3 && ok; ++a) {
      const int b = (a + 1) % 3;
      const double ls = ((*scan)[si[a]].getVector3fMap() - (*scan)[si[b]].getVector3fMap()).norm();
      const double lr = ((*ref)[ri[a]].getVector3fMap() - (*ref)[ri[b]].getVector3fMap()).norm();
      ok = ls > voxel && lr > voxel && std::min(ls, lr) >= s.similarity * std::max(ls, lr);
    }
    if (!ok) continue;
    Eigen::Matrix3d P, Q;  // reference and scan points as columns
    for (int j = 0; j < 3; ++j) {
      P.col(j) = (*ref)[ri[j]].getVector3fMap().cast<double>();
      Q.col(j) = (*scan)[si[j]].getVector3fMap().cast<double>();
    }
    const Eigen::Matrix4d M = Eigen::umeyama(P, Q, false);  // T_scan_ref
    if (!M.allFinite()) continue;
    const Eigen::Quaterniond q(Eigen::Matrix3d(M.topLeftCorner<3, 3>()));
    if (q0 && std::abs(q.normalized().dot(*q0)) < cos_gate) continue;  // Algorithm 1, line 5
    Pose H = Pose::Identity();
    H.matrix() = M;
    const Pose Hinv = H.inverse();
    size_t inliers = 0;
    for (size_t i = 0; i < scan->size(); ++i) {
      PointT p;
      p.getVector3fMap() = (Hinv * (*scan)[i].getVector3fMap().cast<double>()).cast<float>();
      if (rtree.nearestKSearch(p, 1, nn, nd) > 0 && nd[0] <= max_d * max_d) ++inliers;
      // Give up on a hypothesis that can no longer beat the best one.
      if (inliers + (scan->size() - i - 1) <= best_inliers) break;
    }
    if (inliers > best_inliers) best_inliers = inliers, T = H;
  }
  return best_inliers >= s.inlier_fraction * scan->size();
}

}  // namespace laserfit::registration
