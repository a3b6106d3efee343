// Normal Distributions Transform (Magnusson 2009), PCL.
#include <pcl/registration/ndt.h>

#include "refine_pcl.hpp"

namespace laserfit::registration {

RefineOutput refine_ndt(const RefineInput& in) {
  pcl::NormalDistributionsTransform<PointT, PointT> ndt;
  ndt.setResolution(float(4 * in.voxel));  // cells of a few voxels
  ndt.setStepSize(in.voxel);
  ndt.setInputSource(in.scan);  // scan -> model, as for the ICP variants
  ndt.setInputTarget(in.ref);
  ndt.setMaximumIterations(in.s.max_iterations);
  ndt.setTransformationEpsilon(in.s.convergence_mm * in.s.convergence_mm);
  PclCloud aligned;
  ndt.align(aligned, to_matrix4f(in.init.inverse()));
  RefineOutput out;
  out.T = from_matrix4f(ndt.getFinalTransformation()).inverse();
  out.iterations = ndt.getFinalNumIteration();
  return out;
}

}  // namespace laserfit::registration
