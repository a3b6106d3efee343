#pragma once
// The reference side of a registration, prepared once per (reference, settings) and shared: a
// benchmark registers the same reference in every trial, and one registration registers it
// against up to max_clusters parts and a regrown crop. Private to lib/registration.
#include <memory>
#include <mutex>
#include <vector>

#include "stages.hpp"

namespace laserfit::registration {

// A rigid motion that lays the reference back onto itself, started as a rotation about one of its
// principal axes (through its centroid) or a product of two such, and aligned: a candidate
// near-symmetry (twins.cpp).
struct Twin {
  Pose S;                   // reference frame -> reference frame
  double self_overlap = 0;  // fraction of its points within 1 voxel of it after S
  double angle_deg = 0;
  Eigen::Vector3d axis;  // reference frame, unit
};

struct PreparedReference {
  PclCloud::Ptr ref;       // dense samples with their normals (estimated when the file had none)
  Tree::Ptr tree;          // over ref
  PclCloud::Ptr coarse;    // the RANSAC stage's grid (null when not asked for)
  Features::Ptr features;  // its FPFH
  double voxel = 0;        // mm, what it was prepared at (part of the cache key)
  // Its near-symmetries (twins.cpp), found on first use: only an ok pose needs them.
  const std::vector<Twin>& twins() const;

 private:
  mutable std::once_flag twins_once_;
  mutable std::vector<Twin> twins_;
};
// The candidate near-symmetries of `ref` (twins.cpp) that turn it by at most max_turn_deg, every
// one with its self-overlap.
std::vector<Twin> reference_twins(const PclCloud& ref, const Tree& tree, double voxel,
                                  double max_turn_deg = 180);

// `ref` prepared at `voxel` (mm) with s's pre-processing and, when `with_features`, the coarse
// grid and FPFH of s.coarse. Memoised by content (the points' and normals' bytes and every
// setting used), a few entries; thread-safe; the same bytes whatever the thread count.
std::shared_ptr<const PreparedReference> prepared_reference(const PointCloud& ref,
                                                            const RegistrationSettings& s,
                                                            double voxel, bool with_features);

}  // namespace laserfit::registration
