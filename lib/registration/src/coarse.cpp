// FPFH (Rusu et al. 2009) + RANSAC with pre-rejection (Buch et al. 2013), as in the paper's
// Algorithm 1, line 4, on PCL.
#include <pcl/features/fpfh_omp.h>
#include <pcl/registration/sample_consensus_prerejective.h>

#include <cstdlib>
#include <mutex>

#include "laserfit/core/cpu_budget.hpp"
#include "stages.hpp"

namespace laserfit::registration {

Features::Ptr fpfh(const PclCloud::Ptr& cloud, double radius) {
  pcl::FPFHEstimationOMP<PointT, PointT, pcl::FPFHSignature33> est(threads_or(2));
  est.setInputCloud(cloud);
  est.setInputNormals(cloud);
  est.setSearchMethod(Tree::Ptr(new Tree));
  est.setRadiusSearch(radius);
  Features::Ptr f(new Features);
  est.compute(*f);
  return f;
}

bool coarse_align(const PclCloud::Ptr& ref, const Features::Ptr& ref_f, const PclCloud::Ptr& scan,
                  const Features::Ptr& scan_f, const CoarseSettings& s, double voxel, uint64_t seed,
                  Pose& T) {
  pcl::SampleConsensusPrerejective<PointT, PointT, pcl::FPFHSignature33> ransac;
  // The scan is the source: it sees only part of the reference (one view, occlusions), so the
  // inlier fraction is asked of the scan, which should lie almost entirely on the reference.
  ransac.setInputSource(scan);
  ransac.setSourceFeatures(scan_f);
  ransac.setInputTarget(ref);
  ransac.setTargetFeatures(ref_f);
  ransac.setMaximumIterations(s.ransac_iterations);
  ransac.setNumberOfSamples(s.samples);
  ransac.setCorrespondenceRandomness(s.correspondence_randomness);
  ransac.setSimilarityThreshold(float(s.similarity));
  ransac.setMaxCorrespondenceDistance(s.max_correspondence_vox * voxel);
  ransac.setInlierFraction(float(s.inlier_fraction));
  // PCL draws its samples with std::rand(), one sequence for the whole process: seeded here and
  // held under a lock, or two registrations at once (`laserfit bench --jobs 2`) interleave their
  // draws and a trial's pose depends on its neighbour's timing (one needle trial of the paper
  // method gave three different poses in three runs).
  static std::mutex rand_mutex;
  const std::lock_guard<std::mutex> lock(rand_mutex);
  std::srand(static_cast<unsigned>(seed % 2147483647u));
  PclCloud aligned;
  ransac.align(aligned);
  if (!ransac.hasConverged()) return false;
  T = from_matrix4f(ransac.getFinalTransformation()).inverse();  // T_ref_scan -> T_scan_ref
  return true;
}

}  // namespace laserfit::registration
