// Memo of prepared references (reference_cache.hpp). The key hashes the cloud's content rather
// than its address: a benchmark's reference is a fresh copy per trial.
#include "reference_cache.hpp"

#include <cstring>
#include <list>
#include <mutex>

namespace laserfit::registration {
namespace {

struct Key {
  uint64_t content = 0;
  double voxel = 0, normal_radius_vox = 0, voxel_factor = 0, feature_radius_vox = 0;
  bool features = false;
  bool operator==(const Key& o) const {
    return content == o.content && voxel == o.voxel && normal_radius_vox == o.normal_radius_vox &&
           voxel_factor == o.voxel_factor && feature_radius_vox == o.feature_radius_vox &&
           features == o.features;
  }
};

// FNV-1a (64 bit) over the points, then the normals (their count first: a cloud without normals
// differs from one with).
uint64_t content_hash(const PointCloud& c) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* data, size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (const auto* v : {&c.points, &c.normals}) {
    const uint64_t n = v->size();
    mix(&n, sizeof n);
    if (n) mix(v->data(), n * sizeof(Eigen::Vector3f));
  }
  return h;
}

std::shared_ptr<const PreparedReference> prepare(const PointCloud& in,
                                                 const RegistrationSettings& s, double voxel,
                                                 bool with_features) {
  auto out = std::make_shared<PreparedReference>();
  out->voxel = voxel;
  PreprocessSettings pre = s.pre;
  pre.use_viewpoint = false, pre.outlier_std = 0;  // CAD samples have no outliers
  // The dense CAD samples keep their exact normals for refinement and assessment; without
  // normals, they are estimated.
  out->ref = in.has_normals() ? to_pcl(in) : registration::prepare(in, pre, voxel);
  out->tree.reset(new Tree);
  out->tree->setInputCloud(out->ref);
  if (with_features) {
    const double cvox = s.coarse.voxel_factor * voxel;
    out->coarse = coarser(out->ref, cvox, pre, true);
    out->features = fpfh(out->coarse, s.coarse.feature_radius_vox * cvox);
  }
  return out;
}

constexpr size_t kEntries = 8;  // references in use at once: a cell's parts, a benchmark's targets

}  // namespace

std::shared_ptr<const PreparedReference> prepared_reference(const PointCloud& ref,
                                                            const RegistrationSettings& s,
                                                            double voxel, bool with_features) {
  const Key key{content_hash(ref),           voxel,
                s.pre.normal_radius_vox,     s.coarse.voxel_factor,
                s.coarse.feature_radius_vox, with_features};
  static std::mutex m;
  static std::list<std::pair<Key, std::shared_ptr<const PreparedReference>>> memo;  // newest first
  {
    const std::lock_guard<std::mutex> lock(m);
    for (auto it = memo.begin(); it != memo.end(); ++it)
      if (it->first == key) {
        memo.splice(memo.begin(), memo, it);
        return memo.front().second;
      }
  }
  // Prepared outside the lock: two threads may prepare the same reference at once, to the same
  // bytes; the second insertion is a duplicate entry that ages out.
  auto prepared = prepare(ref, s, voxel, with_features);
  const std::lock_guard<std::mutex> lock(m);
  memo.emplace_front(key, prepared);
  if (memo.size() > kEntries) memo.pop_back();
  return prepared;
}

const std::vector<Twin>& PreparedReference::twins() const {
  std::call_once(twins_once_, [&] { twins_ = reference_twins(*ref, *tree, voxel); });
  return twins_;
}

}  // namespace laserfit::registration
