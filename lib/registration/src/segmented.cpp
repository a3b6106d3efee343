// Registration of one part of a scan that holds several (register_segmented): the scan is split
// into candidate parts, each registered with register_cloud, and a pose that one part alone cannot
// pin is registered again on all the scan points near it. crop_near is the crop both use.
#include <chrono>
#include <map>

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
// to keep, but it is where the arm says it is. `order`: the parts nearest the prior first, else
// the largest first.
std::vector<PointCloud> candidate_parts(const PointCloud& scan, const PointCloud& ref,
                                        const RegistrationSettings& s, double voxel,
                                        std::vector<int>& order) {
  auto parts = segment_clusters(scan, voxel, 3 * voxel, 20);
  if (s.prior) {
    PointCloud near = crop_near(scan, ref, *s.prior, s.prior_radius_mm);
    if (near.points.size() >= 10) parts.insert(parts.begin(), std::move(near));
  }
  if (parts.empty()) throw Error("no part of the scan is large enough to register");
  order.resize(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) order[i] = int(i);
  if (!s.prior) return parts;
  Eigen::Vector3f c = Eigen::Vector3f::Zero();
  size_t n = 0;
  for (const auto& p : ref.points)
    if (p.allFinite()) c += p, ++n;
  const Eigen::Vector3f at =
      (*s.prior * (c / float(std::max<size_t>(n, 1))).cast<double>()).cast<float>();
  std::vector<float> dist(parts.size(), std::numeric_limits<float>::infinity());
  for (size_t i = 0; i < parts.size(); ++i)
    for (const auto& p : parts[i].points) dist[i] = std::min(dist[i], (p - at).squaredNorm());
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist[a] < dist[b]; });
  return parts;
}

// Registers the first max_clusters parts, stopping at the first ok; the best result (ok before
// ambiguous before failed; equal ranks: with a prior the earlier, nearer part — a thread
// registered onto the needle's shaft fits as well as onto the thread; without one, the lower
// fitness) and its index in `parts`.
std::pair<RegistrationResult, int> register_parts(const std::vector<PointCloud>& parts,
                                                  const std::vector<int>& order,
                                                  const PointCloud& ref,
                                                  const RegistrationSettings& s, int max_clusters) {
  // A part's slide search is left to the regrown registration: it sees every piece of the part,
  // the cluster may have lost what pins it.
  RegistrationSettings each = s;
  each.trust.slide_range_mm = 0;
  RegistrationResult best;
  int best_i = -1;
  std::map<std::string, double> spent;  // every part tried, not only the one kept
  for (int k = 0; k < int(order.size()) && k < max_clusters; ++k) {
    const int i = order[k];
    if (parts[i].points.size() < 10) continue;
    RegistrationResult r;
    try {
      r = register_cloud(parts[i], ref, each);
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
  check_slide_settings(s.trust);
  const auto t0 = std::chrono::steady_clock::now();
  PointCloud scan = scan_in;
  remove_mixed_pixels(scan);
  const double voxel = s.pre.voxel_mm > 0 ? s.pre.voxel_mm : auto_voxel_mm(ref);
  std::vector<int> order;
  const std::vector<PointCloud> parts = candidate_parts(scan, ref, s, voxel, order);
  const double t_segment =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  auto [best, best_i] = register_parts(parts, order, ref, s, max_clusters);
  if (s.policies.regrow && regrow(scan, ref, s, best)) best_i = int(parts.size());
  if (cluster) *cluster = best_i;
  best.part = best_i;
  best.timings_s["segment"] = t_segment;
  best.log.push_back("segmentation: " + std::to_string(parts.size()) +
                     " candidate parts, registered part " + std::to_string(best_i));
  return best;
}

}  // namespace laserfit::registration
