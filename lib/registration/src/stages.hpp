#pragma once
// The stages of Algorithm 1 (private to lib/registration).
#include <pcl/features/fpfh.h>

#include "laserfit/registration/registration.hpp"
#include "pcl_types.hpp"

namespace laserfit::registration {

using Features = pcl::PointCloud<pcl::FPFHSignature33>;
Features::Ptr fpfh(const PclCloud::Ptr& cloud, double radius_mm);

// One RANSAC attempt (Algorithm 1, line 4): FPFH correspondences, SampleConsensusPrerejective.
// Seeded; returns false when no hypothesis reached the inlier fraction.
bool coarse_align(const PclCloud::Ptr& ref, const Features::Ptr& ref_f, const PclCloud::Ptr& scan,
                  const Features::Ptr& scan_f, const CoarseSettings& s, double voxel, uint64_t seed,
                  Pose& T_scan_ref);

// Refinement (Algorithm 1, line 6) with the named variant.
struct RefineInput {
  PclCloud::Ptr ref, scan;     // ref: dense CAD samples with their exact normals
  Tree::Ptr scan_tree, ref_tree;
  Pose init;
  double voxel;
  const RefineSettings& s;
};
struct RefineOutput {
  Pose T = Pose::Identity();
  int iterations = 0;
};
using RefineFn = RefineOutput (*)(const RefineInput&);
RefineFn find_refiner(const std::string& name);  // throws Error listing the names

// The variants, one small file each (refine_*.cpp); registered in refiners.cpp.
RefineOutput refine_point_to_point(const RefineInput& in);
RefineOutput refine_point_to_plane(const RefineInput& in);
RefineOutput refine_gicp(const RefineInput& in);
RefineOutput refine_ndt(const RefineInput& in);
RefineOutput refine_ceres(const RefineInput& in);

// Fit statistics and the trust decision for a final pose, measured from the scan side: the scan
// (one view, segmented to the object) should lie on the reference, while most of the reference
// is legitimately unseen. fitness = mean squared point-to-plane distance (reference normals) of
// the scan points whose nearest reference point is within the gate — with dense CAD samples this
// measures misalignment, not sampling density; overlap = fraction of scan points within the gate.
struct Fit {
  double fitness_mm2 = 0, rmse_mm = 0, overlap = 0;
  size_t inliers = 0;
};
Fit evaluate(const PclCloud& scan, const Tree& ref_tree, const Pose& T_scan_ref, double gate_mm);
// The point-to-plane normal equations at pose T (scaled Hessian H, residual sum, RMS radius L).
struct PlaneSystem {
  Matrix6d H = Matrix6d::Zero();
  double residual2 = 0, L = 1;
  size_t n = 0;
};
PlaneSystem plane_system(const PclCloud& scan, const Tree& ref_tree, const Pose& T, double gate_mm);
void assess(const PclCloud& scan, const Tree& ref_tree, double gate_mm, const TrustSettings& t,
            double voxel, RegistrationResult& r);

}  // namespace laserfit::registration
