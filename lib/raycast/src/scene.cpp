#include "laserfit/raycast/scene.hpp"

#include <embree3/rtcore.h>

#include <string>

#include "laserfit/core/error.hpp"

namespace laserfit::raycast {
namespace {

// Embree reports through a C callback; never throw across it, check the device afterwards.
void check(RTCDevice device, const char* during) {
  const RTCError code = rtcGetDeviceError(device);
  if (code != RTC_ERROR_NONE)
    throw Error(std::string("Embree failed during ") + during + " (error code " +
                std::to_string(static_cast<int>(code)) + ")");
}

// Packets of 16 rays where Embree runs them natively (AVX-512), else of 8 (AVX2); the
// overloads pick Embree's entry point by packet type.
template <int N>
struct Packet;
template <>
struct Packet<8> {
  using RayHit = RTCRayHit8;
  using Ray = RTCRay8;
};
template <>
struct Packet<16> {
  using RayHit = RTCRayHit16;
  using Ray = RTCRay16;
};
void packet_intersect(const int* v, RTCScene s, RTCIntersectContext* c, RTCRayHit8* r) {
  rtcIntersect8(v, s, c, r);
}
void packet_intersect(const int* v, RTCScene s, RTCIntersectContext* c, RTCRayHit16* r) {
  rtcIntersect16(v, s, c, r);
}
void packet_occluded(const int* v, RTCScene s, RTCIntersectContext* c, RTCRay8* r) {
  rtcOccluded8(v, s, c, r);
}
void packet_occluded(const int* v, RTCScene s, RTCIntersectContext* c, RTCRay16* r) {
  rtcOccluded16(v, s, c, r);
}

}  // namespace

struct Scene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<std::vector<Eigen::Vector3f>> normals;  // per geometry, per triangle (scene frame)
  size_t triangles = 0;
  bool committed = false;
  bool wide = false;  // native 16-wide packets

  template <int N>
  void fan(const Eigen::Vector3f& o, const std::vector<Eigen::Vector3f>& dirs, float tnear,
           float tfar, std::vector<Hit>& hits) const;
  template <int N>
  void segments(const std::vector<Eigen::Vector3f>& from, const std::vector<Eigen::Vector3f>& to,
                const std::vector<uint8_t>& active, float eps, std::vector<uint8_t>& clear) const;
};

Scene::Scene(PacketWidth packets) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("verbose=0");
  if (!impl_->device) throw Error("Embree: cannot create device");
  impl_->wide =
      packets == PacketWidth::native
          ? rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) == 1
          : packets == PacketWidth::w16;
  impl_->scene = rtcNewScene(impl_->device);
  // Robust traversal: no ray slips through a shared edge, which would punch false holes into the
  // shadow tests of a watertight part.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
}

Scene::~Scene() {
  if (!impl_) return;
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

int Scene::add_mesh(const TriMesh& mesh, const Pose& T) {
  if (mesh.empty()) throw Error("cannot add an empty mesh to the ray-casting scene");
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  const Eigen::Affine3f Tf = T.cast<float>();
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3f p = Tf * mesh.vertices[i];
    v[3 * i] = p.x(), v[3 * i + 1] = p.y(), v[3 * i + 2] = p.z();
  }
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.faces.size()));
  std::vector<Eigen::Vector3f> nrm(mesh.faces.size());
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) idx[3 * f + k] = static_cast<unsigned>(mesh.faces[f][k]);
    nrm[f] = Tf.linear() * mesh.face_normal(static_cast<int>(f));
  }
  rtcCommitGeometry(g);
  check(impl_->device, "geometry setup");
  const unsigned id = rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  if (id != impl_->normals.size()) throw Error("Embree: unexpected geometry id");
  impl_->normals.push_back(std::move(nrm));
  impl_->triangles += mesh.faces.size();
  impl_->committed = false;
  return static_cast<int>(id);
}

void Scene::commit() {
  rtcCommitScene(impl_->scene);
  check(impl_->device, "BVH build");
  impl_->committed = true;
}

size_t Scene::triangle_count() const { return impl_->triangles; }

Hit Scene::intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear,
                     float tfar) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray.org_x = o.x(), rh.ray.org_y = o.y(), rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x(), rh.ray.dir_y = d.y(), rh.ray.dir_z = d.z();
  rh.ray.tnear = tnear, rh.ray.tfar = tfar;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rh.ray.tfar;
  h.geom = static_cast<int>(rh.hit.geomID);
  h.prim = static_cast<int>(rh.hit.primID);
  h.normal = impl_->normals[h.geom][h.prim];
  return h;
}

bool Scene::occluded(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear,
                     float tfar) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r{};
  r.org_x = o.x(), r.org_y = o.y(), r.org_z = o.z();
  r.dir_x = d.x(), r.dir_y = d.y(), r.dir_z = d.z();
  r.tnear = tnear, r.tfar = tfar;
  r.mask = 0xFFFFFFFFu;
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0.f;  // Embree sets tfar = -inf on a hit
}

bool Scene::segment_clear(const Eigen::Vector3f& from, const Eigen::Vector3f& to, float eps) const {
  const Eigen::Vector3f d = to - from;
  const float len = d.norm();
  if (len <= 2 * eps) return true;
  return !occluded(from, d / len, eps, len - eps);
}

void Scene::intersect_fan(const Eigen::Vector3f& o, const std::vector<Eigen::Vector3f>& dirs,
                          float tnear, float tfar, std::vector<Hit>& hits) const {
  if (impl_->wide) return impl_->fan<16>(o, dirs, tnear, tfar, hits);
  impl_->fan<8>(o, dirs, tnear, tfar, hits);
}

template <int kPacket>
void Scene::Impl::fan(const Eigen::Vector3f& o, const std::vector<Eigen::Vector3f>& dirs,
                      float tnear, float tfar, std::vector<Hit>& hits) const {
  hits.assign(dirs.size(), Hit{});
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // rays of a fan share origin and direction
  alignas(64) typename Packet<kPacket>::RayHit rh;
  alignas(64) int valid[kPacket];
  for (size_t base = 0; base < dirs.size(); base += kPacket) {
    for (int k = 0; k < kPacket; ++k) {
      const size_t i = base + k;
      valid[k] = i < dirs.size() ? -1 : 0;
      const Eigen::Vector3f& d = i < dirs.size() ? dirs[i] : dirs[base];
      rh.ray.org_x[k] = o.x(), rh.ray.org_y[k] = o.y(), rh.ray.org_z[k] = o.z();
      rh.ray.dir_x[k] = d.x(), rh.ray.dir_y[k] = d.y(), rh.ray.dir_z[k] = d.z();
      rh.ray.tnear[k] = tnear, rh.ray.tfar[k] = tfar;
      rh.ray.mask[k] = 0xFFFFFFFFu, rh.ray.time[k] = 0.f, rh.ray.flags[k] = 0;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
    packet_intersect(valid, scene, &ctx, &rh);
    for (int k = 0; k < kPacket && base + k < dirs.size(); ++k) {
      if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
      Hit& h = hits[base + k];
      h.t = rh.ray.tfar[k];
      h.geom = static_cast<int>(rh.hit.geomID[k]);
      h.prim = static_cast<int>(rh.hit.primID[k]);
      h.normal = normals[h.geom][h.prim];
    }
  }
}

void Scene::segments_clear(const std::vector<Eigen::Vector3f>& from,
                           const std::vector<Eigen::Vector3f>& to,
                           const std::vector<uint8_t>& active, float eps,
                           std::vector<uint8_t>& clear) const {
  if (impl_->wide) return impl_->segments<16>(from, to, active, eps, clear);
  impl_->segments<8>(from, to, active, eps, clear);
}

template <int kPacket>
void Scene::Impl::segments(const std::vector<Eigen::Vector3f>& from,
                           const std::vector<Eigen::Vector3f>& to,
                           const std::vector<uint8_t>& active, float eps,
                           std::vector<uint8_t>& clear) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  alignas(64) typename Packet<kPacket>::Ray r;
  alignas(64) int valid[kPacket];
  // Gather active rays into full packets (inactive ones would waste packet lanes).
  std::vector<size_t> idx;
  for (size_t i = 0; i < from.size(); ++i)
    if (active[i]) idx.push_back(i);
  for (size_t base = 0; base < idx.size(); base += kPacket) {
    for (int k = 0; k < kPacket; ++k) {
      valid[k] = 0;
      if (base + k >= idx.size()) continue;
      const size_t i = idx[base + k];
      const Eigen::Vector3f d = to[i] - from[i];
      const float len = d.norm();
      if (len <= 2 * eps) continue;  // nothing in between: clear
      valid[k] = -1;
      const Eigen::Vector3f u = d / len;
      r.org_x[k] = from[i].x(), r.org_y[k] = from[i].y(), r.org_z[k] = from[i].z();
      r.dir_x[k] = u.x(), r.dir_y[k] = u.y(), r.dir_z[k] = u.z();
      r.tnear[k] = eps, r.tfar[k] = len - eps;
      r.mask[k] = 0xFFFFFFFFu, r.time[k] = 0.f, r.flags[k] = 0;
    }
    packet_occluded(valid, scene, &ctx, &r);
    for (int k = 0; k < kPacket && base + k < idx.size(); ++k)
      clear[idx[base + k]] = valid[k] == 0 || r.tfar[k] >= 0.f;
  }
}

}  // namespace laserfit::raycast
