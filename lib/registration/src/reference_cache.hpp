#pragma once
// The reference side of a registration, prepared once per (reference, settings) and shared: a
// benchmark registers the same reference in every trial, and one registration registers it
// against up to max_clusters parts and a regrown crop. Private to lib/registration.
#include <memory>

#include "stages.hpp"

namespace laserfit::registration {

struct PreparedReference {
  PclCloud::Ptr ref;       // dense samples with their normals (estimated when the file had none)
  Tree::Ptr tree;          // over ref
  PclCloud::Ptr coarse;    // the RANSAC stage's grid (null when not asked for)
  Features::Ptr features;  // its FPFH
};

// `ref` prepared at `voxel` (mm) with s's pre-processing and, when `with_features`, the coarse
// grid and FPFH of s.coarse. Memoised by content (the points' and normals' bytes and every
// setting used), a few entries; thread-safe; the same bytes whatever the thread count.
std::shared_ptr<const PreparedReference> prepared_reference(const PointCloud& ref,
                                                            const RegistrationSettings& s,
                                                            double voxel, bool with_features);

}  // namespace laserfit::registration
