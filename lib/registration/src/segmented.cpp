// Registration of one part of a scan that holds several (register_segmented): the scan is split
// into candidate parts, each registered with register_cloud, and a pose that one part alone cannot
// pin is registered again on all the scan points near it. crop_near is the crop both use.
#include <limits>
#include <map>

#include "driver.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/registration/preprocess.hpp"
#include "slide.hpp"
#include "stages.hpp"

namespace laserfit::registration {

PointCloud crop_near(const PointCloud& scan, const PointCloud& ref, const Pose& T_scan_ref,
                     double radius, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  // Copies slid at most one radius apart: their balls overlap, so the crop is one swept tube.
  const int n = radius > 0 ? int(std::ceil((to - from).norm() / radius - 1e-9)) : 0;
  std::vector<Eigen::Vector3f> placed;
  placed.reserve(size_t(n + 1) * ref.points.size());  // millions of points for a swept crop
  Eigen::AlignedBox3f box;
  for (int k = 0; k <= n; ++k) {
    const Pose T =
        Eigen::Translation3d(from + (n ? double(k) / n : 0.0) * (to - from)) * T_scan_ref;
    for (const auto& p : ref.points) {
      if (!p.allFinite()) continue;
      placed.push_back((T * p.cast<double>()).cast<float>());
      box.extend(placed.back());
    }
  }
  PointCloud out;
  out.metadata = scan.metadata, out.sensor_origin = scan.sensor_origin;
  if (placed.empty()) return out;
  box.min().array() -= float(radius), box.max().array() += float(radius);
  std::vector<size_t> at;
  std::vector<Eigen::Vector3f> queries;
  at.reserve(scan.points.size()), queries.reserve(scan.points.size());
  for (size_t i = 0; i < scan.points.size(); ++i)
    if (scan.points[i].allFinite() && box.contains(scan.points[i]))
      queries.push_back(scan.points[i]), at.push_back(i);
  // Radius-bounded and batched: most scan points are far from the part, and an unbounded nearest
  // search from them descends much of the tree (the o2ac panel's 1.5 M points against a crop
  // swept 20 mm: an 18-minute registration, then 10 s); one PCL query per
  // point opened an OpenMP region in FLANN per point (0.7 s of a 1 M-point scan's 1.4 s).
  const std::vector<char> near = within_radius(placed, queries, radius);
  const bool labels = !scan.labels.empty();
  for (size_t k = 0; k < at.size(); ++k) {
    if (!near[k]) continue;
    out.points.push_back(scan.points[at[k]]);
    if (labels) out.labels.push_back(scan.labels[at[k]]);
  }
  out.width = int(out.points.size());
  out.height = 1;
  return out;
}

namespace {

int rank(const RegistrationResult& r) {
  return r.status == Status::Ok ? 0 : r.status == Status::Ambiguous ? 1 : 2;
}

// The candidate parts in the order to try them. Parts further apart than 3 voxels are separate; a
// part needs at least 20 voxels (a 0.15 mm thread tip seen over a millimetre is a few dozen).
// With a prior, the scan points near the reference placed there are one more candidate, tried
// first: a sparse part (a thin thread seen along its length) falls apart into clusters too small
// to keep, but it is where the arm says it is. The order: the parts nearest the prior first, else
// the largest first.
// Clustering a 1.7 M-point scan takes a tenth of a second or more, and the points near the prior
// are usually registered `ok` on their own: the clusters are found only when a second candidate
// is needed, unless a cluster could come before those points (a scan point nearer the prior than
// any of them), when they are found at once. Either way the order is the same.
class Candidates {
 public:
  Candidates(const PointCloud& scan, const PointCloud& ref, const RegistrationSettings& s,
             double voxel)
      : scan_(scan), s_(s), voxel_(voxel) {
    const auto t0 = Clock::now();
    if (s.prior) {
      at_ = placed_centroid(ref, *s.prior);
      PointCloud near = crop_near(scan, ref, *s.prior, s.prior_radius_mm);
      if (near.points.size() >= 10 && nearest(near) <= nearest(scan)) order_ = {0};
      if (near.points.size() >= 10) parts_.push_back(std::move(near));
    }
    if (order_.empty()) cluster();
    seconds += since(t0);
  }
  // The k-th part to try, nullptr after the last; `index`: its place among all the parts (the
  // points near the prior first, then the clusters, largest first).
  const PointCloud* part(size_t k, int& index) {
    if (k >= order_.size() && !clustered_) {
      const auto t0 = Clock::now();
      cluster();
      seconds += since(t0);
    }
    if (k >= order_.size()) return nullptr;
    index = order_[k];
    return &parts_[size_t(index)];
  }
  std::string describe() const {
    return clustered_ ? std::to_string(parts_.size()) + " candidate parts"
                      : "the points near the prior (not clustered)";
  }
  double seconds = 0;

 private:
  static Eigen::Vector3f placed_centroid(const PointCloud& ref, const Pose& T) {
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    size_t n = 0;
    for (const auto& p : ref.points)
      if (p.allFinite()) c += p, ++n;
    return (T * (c / float(std::max<size_t>(n, 1))).cast<double>()).cast<float>();
  }
  float nearest(const PointCloud& c) const {  // squared distance to the placed centroid
    float d = std::numeric_limits<float>::infinity();
    for (const auto& p : c.points)
      if (p.allFinite()) d = std::min(d, (p - at_).squaredNorm());
    return d;
  }
  void cluster() {
    auto clusters = segment_clusters(scan_, voxel_, 3 * voxel_, 20);
    for (auto& c : clusters) parts_.push_back(std::move(c));
    clustered_ = true;
    if (parts_.empty()) throw Error("no part of the scan is large enough to register");
    order_.resize(parts_.size());
    for (size_t i = 0; i < parts_.size(); ++i) order_[i] = int(i);
    if (!s_.prior) return;
    std::vector<float> dist(parts_.size());
    for (size_t i = 0; i < parts_.size(); ++i) dist[i] = nearest(parts_[i]);
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int a, int b) { return dist[size_t(a)] < dist[size_t(b)]; });
  }
  const PointCloud& scan_;
  const RegistrationSettings& s_;
  const double voxel_;
  Eigen::Vector3f at_ = Eigen::Vector3f::Zero();
  std::vector<PointCloud> parts_;
  std::vector<int> order_;
  bool clustered_ = false;
};

// Registers the first max_clusters parts, stopping at the first ok; the best result (ok before
// ambiguous before failed; equal ranks: with a prior the earlier, nearer part — a thread
// registered onto the needle's shaft fits as well as onto the thread; without one, the lower
// fitness) and its index among the parts.
std::pair<RegistrationResult, int> register_parts(Candidates& parts, const PointCloud& ref,
                                                  const RegistrationSettings& s, int max_clusters) {
  // A part's slide search is left to the regrown registration: it sees every piece of the part,
  // the cluster may have lost what pins it.
  RegistrationSettings each = s;
  each.trust.slide_range_mm = 0;
  RegistrationResult best;
  int best_i = -1, i = -1;
  std::map<std::string, double> spent;  // every part tried, not only the one kept
  for (int k = 0; k < max_clusters; ++k) {
    const PointCloud* part = parts.part(size_t(k), i);
    if (!part) break;
    if (part->points.size() < 10) continue;
    RegistrationResult r;
    try {
      r = register_cloud(*part, ref, each);
    } catch (const Error& e) {  // a candidate too small to register is a failed candidate
      r.status = Status::Failed;
      r.reason = "part " + std::to_string(i) + ": " + e.what();
    }
    for (const auto& [stage, t] : r.timings_s) spent[stage] += t;
    if (best_i < 0 || rank(r) < rank(best) ||
        (rank(r) == rank(best) && !s.prior && r.fitness_mm2 < best.fitness_mm2))
      best = std::move(r), best_i = i;
    if (best.status == Status::Ok) break;
  }
  best.timings_s = std::move(spent);
  return {std::move(best), best_i};
}

// A part cut in two by another's shadow (the thread across the needle's eye) leaves clusters that
// miss what pins it (the needle's end beyond the shadow): their pose slides along the shaft and
// comes back ambiguous. Near the pose found, every piece of the part is within reach: registered
// once more on all scan points near the reference placed there. True when that was better.
bool regrow(const PointCloud& scan, const PointCloud& ref, const RegistrationSettings& s,
            RegistrationResult& best) {
  if (best.status == Status::Failed || best.unobservable == 0) return false;
  // A pose flat along a translation may be anywhere on the plateau its equally good attempts
  // spread over, and up to the slide range beyond: the crop and the slide search reach that far
  // along it, or they miss what pins the part (the needle's head beyond its eye).
  RegistrationSettings g = s;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  const auto flat = flat_translation(best, s.trust);
  if (flat && s.trust.slide_range_mm > 0) {
    const double range = s.trust.slide_range_mm;
    from = (best.flat_from_mm - range) * *flat, to = (best.flat_to_mm + range) * *flat;
    g.trust.slide_range_mm = std::min(range + std::max(-best.flat_from_mm, best.flat_to_mm),
                                      max_slide_steps * s.trust.slide_step_mm);
  }
  const PointCloud grown = crop_near(scan, ref, best.T_scan_ref, s.prior_radius_mm, from, to);
  if (grown.points.size() < 10) return false;
  // Flat along one translation (a shaft), the part slides on a line the crop and the slide search
  // cover: refining from the pose found is enough. Flat in more (a piece of plate: two
  // translations and a spin) it may sit anywhere on that plane and the pose found is a guess: the
  // grown crop is registered afresh (that pose first, then RANSAC) with the rival and
  // confirmation checks of any registration (refined from the guess, the o2ac panel came back ok
  // 15.6 mm off, explaining half the crop).
  g.prior = best.T_scan_ref, g.skip_coarse = flat && best.flat == 1;
  try {
    RegistrationResult r = register_cloud(grown, ref, g);
    const bool better =
        rank(r) < rank(best) || (rank(r) == rank(best) && r.unobservable < best.unobservable);
    best.log.push_back(
        std::string("regrown around the pose found (flat in ") + std::to_string(best.flat) +
        (g.skip_coarse ? ", refined): " : ", registered afresh): ") + status_name(r.status) +
        (r.reason.empty() ? "" : " (" + r.reason + ")") + ", " + std::to_string(r.unobservable) +
        " unobservable direction(s)" + (better ? " -> kept" : " -> not better"));
    if (!better) {
      for (const auto& [k, v] : r.timings_s) best.timings_s[k] += v;  // the time it took
      return false;
    }
    r.log.insert(r.log.begin(), best.log.begin(), best.log.end());
    for (const auto& [k, v] : best.timings_s) r.timings_s[k] += v;
    best = std::move(r);
    return true;
  } catch (const Error& e) {
    best.log.push_back(std::string("regrown around the pose found: ") + e.what());
    return false;
  }
}

}  // namespace

RegistrationResult register_segmented(const PointCloud& scan_in, const PointCloud& ref,
                                      const RegistrationSettings& s, int max_clusters,
                                      int* cluster) {
  if (uses_thin_detector(ref, s)) return detect_thin_part(scan_in, ref, s);  // segments itself
  const CleanedScan c = clean_scan(scan_in);
  return register_cleaned(c.scan, c.seconds, ref, s, max_clusters, cluster);
}

CleanedScan clean_scan(const PointCloud& scan) {
  const auto t0 = Clock::now();
  CleanedScan c{scan};
  remove_mixed_pixels(c.scan);
  c.seconds = since(t0);
  return c;
}

RegistrationResult register_cleaned(const PointCloud& scan, double t_clean, const PointCloud& ref,
                                    const RegistrationSettings& s, int max_clusters, int* cluster) {
  check_slide_settings(s.trust);
  const double voxel = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref);
  Candidates parts(scan, ref, s, voxel);
  auto [best, best_i] = register_parts(parts, ref, s, max_clusters);
  if (s.policies.regrow && regrow(scan, ref, s, best)) best_i = kRegrownPart;
  if (cluster) *cluster = best_i;
  best.part = best_i;
  best.timings_s["segment"] = t_clean + parts.seconds;  // with clusters found on demand
  best.log.push_back("segmentation: " + parts.describe() + ", registered part " +
                     std::to_string(best_i));
  return best;
}

}  // namespace laserfit::registration
