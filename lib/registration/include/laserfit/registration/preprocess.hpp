#pragma once
#include "laserfit/registration/registration.hpp"

namespace laserfit::registration {

// The paper's "filter and downsample P_scan" (Algorithm 1, line 1): drop NaN, keep one real
// measurement per voxel (the one nearest the voxel centre: a centroid would sit off the surface
// at edges and bias the pose), statistical outlier removal on what is left, normals (oriented
// towards the viewpoint when asked, else towards the input's own normals).
PointCloud preprocess(const PointCloud& in, const PreprocessSettings& s, double voxel_mm);

// Mixed pixels: on an organized scan (rows = profiles), a point farther than `factor` times the
// median in-profile spacing from both of its profile neighbours sits in a depth jump (half
// foreground, half background) or is a lone outlier; it is set to NaN. Such points form veils
// that bridge separate parts (a thread tip and the needle behind it) and defeat segmentation.
// Returns the number removed; unorganized clouds are left alone.
size_t remove_mixed_pixels(PointCloud& scan, double factor = 4.0);

// Auto voxel size for a reference: its bounding-box diagonal / 150.
double auto_voxel_mm(const PointCloud& ref);

}  // namespace laserfit::registration
