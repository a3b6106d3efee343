#include "laserfit/scan/reference.hpp"

#include "laserfit/sampling/sampling.hpp"

namespace laserfit::scan {

Pose mid_sweep(const ScanSettings& s) {
  Pose step = Pose::Identity();
  step.translation() = s.sweep.direction * (0.5 * s.sweep.length_mm);
  return s.sweep.T_base_sensor_start * step;
}

PointCloud view_reference(const TriMesh& mesh, const Pose& T_base_object, const ScanSettings& s,
                          size_t count, uint64_t seed) {
  sampling::ViewSettings v;
  v.T_mesh_sensor.push_back(T_base_object.inverse() * mid_sweep(s));
  v.geometry = s.sensor;
  sampling::SamplingSettings ss;
  ss.count = count, ss.seed = seed;
  return sampling::sample_visible(mesh, v, ss);
}

}  // namespace laserfit::scan
