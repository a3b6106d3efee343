#pragma once
// Embree ray-casting scene: the one geometric mechanism behind view-dependent reference clouds
// and the laser-scanner simulator, so that a reference cloud for a view is exactly the surface
// the noise-free scanner would see.
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <vector>

#include "laserfit/core/mesh.hpp"
#include "laserfit/core/pose.hpp"

namespace laserfit::raycast {

struct Hit {
  float t = std::numeric_limits<float>::infinity();  // distance along the (unit) ray, mm
  int geom = -1;                                     // which mesh (order of add_mesh)
  int prim = -1;                                     // which triangle of that mesh
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // outward face normal, scene frame
  bool valid() const { return geom >= 0; }
};

// Width of the ray packets of the batch calls: the widest Embree runs natively on this CPU (16
// on AVX-512, else 8), or one forced (Embree emulates a width it has no kernel for). The hits do
// not depend on it.
enum class PacketWidth { native, w8, w16 };

class Scene {
 public:
  explicit Scene(PacketWidth packets = PacketWidth::native);
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  // Adds a mesh placed at T_scene_mesh; returns its geometry index. Call commit() before casting.
  int add_mesh(const TriMesh& mesh, const Pose& T_scene_mesh = Pose::Identity());
  void commit();

  // Directions must be unit length; [tnear, tfar] in mm. Thread-safe after commit().
  Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear = 0.f,
                float tfar = std::numeric_limits<float>::infinity()) const;
  bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear,
                float tfar) const;
  // Is the straight segment from `from` to `to` free of geometry (ends excluded by `eps` mm)?
  bool segment_clear(const Eigen::Vector3f& from, const Eigen::Vector3f& to, float eps) const;

  // Coherent batches (Embree packets of PacketWidth): a laser profile is 2048 rays from one
  // emitter. hits[i] is the first hit of ray (origin, dirs[i]) within [tnear, tfar].
  void intersect_fan(const Eigen::Vector3f& origin, const std::vector<Eigen::Vector3f>& dirs,
                     float tnear, float tfar, std::vector<Hit>& hits) const;
  // clear[i] = segment from[i] -> to[i] free of geometry (ends excluded by eps), for the rays
  // with active[i]; inactive entries are left untouched.
  void segments_clear(const std::vector<Eigen::Vector3f>& from,
                      const std::vector<Eigen::Vector3f>& to, const std::vector<uint8_t>& active,
                      float eps, std::vector<uint8_t>& clear) const;

  size_t triangle_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace laserfit::raycast
