#include "laserfit/sensor/assemble.hpp"

#include <limits>
#include <string>

#include "laserfit/core/error.hpp"

namespace laserfit::sensor {

PointCloud assemble_scan(const io::Profiles& profiles, const std::vector<Pose>& T_base_flange,
                         const Pose& T_flange_sensor) {
  const size_t W = size_t(profiles.width), H = size_t(profiles.count);
  if (W == 0 || H == 0 || profiles.xz.size() != W * H)
    throw Error("profiles: " + std::to_string(profiles.xz.size()) + " points are not " +
                std::to_string(H) + " profiles of " + std::to_string(W));
  if (T_base_flange.size() != H)
    throw Error(std::to_string(T_base_flange.size()) + " flange poses for " + std::to_string(H) +
                " profiles: one pose per profile is needed");
  PointCloud c;
  c.width = profiles.width, c.height = profiles.count;
  c.points.resize(W * H, Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  for (size_t i = 0; i < H; ++i) {
    const Pose T_base_sensor = T_base_flange[i] * T_flange_sensor;
    for (size_t j = 0; j < W; ++j) {
      const Eigen::Vector2f& q = profiles.xz[i * W + j];
      if (q.allFinite())  // composed in double, rounded once, as the scan simulation does
        c.points[i * W + j] = (T_base_sensor * Eigen::Vector3d(q.x(), 0.0, q.y())).cast<float>();
    }
  }
  c.sensor_origin = (T_base_flange[H / 2] * T_flange_sensor).translation();
  c.metadata["frame"] = "base (flange poses x hand-eye)";
  c.metadata["unit"] = "mm";
  return c;
}

}  // namespace laserfit::sensor
