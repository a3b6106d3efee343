#pragma once
// Laser line-scanner simulator: what a triangulation line scanner carried by a robot arm would
// deliver for a scene of CAD meshes, with ground truth. Profiles run in parallel; every random
// draw comes from a generator seeded by (seed, profile), so the output is bit-identical for a seed
// whatever the thread count.
#include <cstdint>
#include <string>
#include <vector>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/mesh.hpp"
#include "laserfit/scan/settings.hpp"

namespace laserfit::scan {

struct SceneObject {
  std::string name;
  std::string mesh_path;  // as given in the scene file
  Pose T_base_object = Pose::Identity();
  bool shiny = false;  // specular / multipath outliers (metal parts)
  TriMesh mesh;        // mm, object frame
};

struct ScanScene {
  std::string file;  // where it was loaded from ("" when built in code)
  std::vector<SceneObject> objects;
  ScanSettings settings;
  uint64_t seed = 1;
};

struct ScanStats {
  size_t rays = 0, hits = 0, valid = 0;
  size_t out_of_range = 0, grazing = 0, camera_shadow = 0;  // geometric losses
  size_t dropouts = 0, outliers = 0, mixed_pixels = 0;      // noise artefacts
};

struct ScanTimings {
  double total_s = 0, bvh_s = 0;
  double laser_s = 0, camera_s = 0, noise_s = 0;  // summed over threads (CPU seconds)
};

struct ScanResult {
  PointCloud cloud;  // base frame, from the nominal sensor poses (what the robot believes);
                     // organized: width = points per profile, height = profiles, NaN = invalid;
                     // labels = index of the object hit (-1 none)
  PointCloud raw;    // the same in the (nominal) sensor frame of each profile: x, y = 0, z
  std::vector<Pose> T_base_sensor_nominal, T_base_sensor_true;  // per profile
  std::vector<Pose> T_scan_object;  // each object as the scan shows it (mid-sweep sensor error)
  ScanStats stats;
  ScanTimings timings;
  uint64_t seed = 0;
};

ScanResult simulate_scan(const ScanScene& scene);

// Loads a scene file (YAML, mm; see datasets/scenes/*.yaml); mesh paths are relative to it.
// Unknown keys, missing meshes, bad poses or impossible settings -> laserfit::Error naming it.
ScanScene load_scene(const std::string& path);

}  // namespace laserfit::scan
