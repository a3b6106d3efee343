// Generalized ICP (Segal et al. 2009), PCL.
#include <pcl/registration/gicp.h>

#include "refine_pcl.hpp"

namespace laserfit::registration {

RefineOutput refine_gicp(const RefineInput& in) {
  pcl::GeneralizedIterativeClosestPoint<PointT, PointT> gicp;
  gicp.setMaxCorrespondenceDistance(in.s.max_correspondence_vox * in.voxel);
  gicp.setCorrespondenceRandomness(10);
  return run_pcl_registration(gicp, in);
}

}  // namespace laserfit::registration
