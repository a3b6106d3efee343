#pragma once
// The view-dependent reference cloud of an object: what a scene's sweep (seen from its mid-sweep
// sensor pose) can see of the object placed at T_base_object. Used wherever a registration needs
// a reference matching the designed view (benchmarks, the controller).
#include <cstdint>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/mesh.hpp"
#include "laserfit/scan/settings.hpp"

namespace laserfit::scan {

Pose mid_sweep(const ScanSettings& s);  // sensor pose halfway along the sweep (base frame)

PointCloud view_reference(const TriMesh& mesh, const Pose& T_base_object, const ScanSettings& s,
                          size_t count, uint64_t seed);

}  // namespace laserfit::scan
