// ICP point-to-point (Besl & McKay 1992), PCL — the paper's ICP.
#include <pcl/registration/icp.h>

#include "refine_pcl.hpp"

namespace laserfit::registration {

RefineOutput refine_point_to_point(const RefineInput& in) {
  pcl::IterativeClosestPoint<PointT, PointT> icp;
  icp.setMaxCorrespondenceDistance(in.s.max_correspondence_vox * in.voxel);
  return run_pcl_registration(icp, in);
}

}  // namespace laserfit::registration
