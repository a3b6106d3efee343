// ICP point-to-plane (Chen & Medioni 1992), PCL.
#include <pcl/registration/icp.h>

#include "refine_pcl.hpp"

namespace laserfit::registration {

RefineOutput refine_point_to_plane(const RefineInput& in) {
  pcl::IterativeClosestPointWithNormals<PointT, PointT> icp;
  icp.setMaxCorrespondenceDistance(in.s.max_correspondence_vox * in.voxel);
  return run_pcl_registration(icp, in);
}

}  // namespace laserfit::registration
