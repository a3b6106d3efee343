#pragma once
#include "laserfit/registration/registration.hpp"

namespace laserfit::registration {

// The paper's "filter and downsample P_scan" (Algorithm 1, line 1): drop NaN, keep one real
// measurement per voxel (the one nearest the voxel centre: a centroid would sit off the surface
// at edges and bias the pose), statistical outlier removal on what is left, normals (oriented
// towards the viewpoint when asked, else towards the input's own normals).
PointCloud preprocess(const PointCloud& in, const PreprocessSettings& s, double voxel_mm);

// Auto voxel size for a reference: its bounding-box diagonal / 150.
double auto_voxel_mm(const PointCloud& ref);

}  // namespace laserfit::registration
