#pragma once
#include "laserfit/registration/registration.hpp"

namespace laserfit::registration {

// The paper's "filter and downsample P_scan" (Algorithm 1, line 1): drop NaN, statistical
// outlier removal, voxel grid, normals (oriented towards the viewpoint when asked).
PointCloud preprocess(const PointCloud& in, const PreprocessSettings& s, double voxel_mm);

// Auto voxel size for a reference: its bounding-box diagonal / 150.
double auto_voxel_mm(const PointCloud& ref);

}  // namespace laserfit::registration
