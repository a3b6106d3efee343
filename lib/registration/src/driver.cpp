// register_cloud: the paper's Algorithm 1 as a driver over named stages (driver.hpp), then the
// policies laserfit adds for automatic failure detection (the paper's future work), each of which
// Policies can switch off. docs/design/registration.md has the measurement behind each.
#include "driver.hpp"

#include "laserfit/core/error.hpp"
#include "slide.hpp"

namespace laserfit::registration {

RegistrationResult register_cloud(const PointCloud& scan, const PointCloud& ref,
                                  const RegistrationSettings& s) {
  check_inputs(scan, ref, s);
  if (uses_thin_detector(ref, s)) return detect_thin_part(scan, ref, s);  // a thread: thin.hpp
  RegistrationResult r;
  const Problem p = prepare_problem(scan, ref, s, r);  // line 1: filter, downsample; FPFH
  Attempts a = run_attempts(p, r);  // lines 2-8: RANSAC, d_phi gate, ICP, until rho_ICP
  const auto t = Clock::now();
  std::optional<Candidate> best = keep_best(p, a, r);  // line 9, assessed (trust.cpp)
  if (best) {
    if (s.policies.prefer_prior) prefer_prior(p, a, *best, r);
    measure_plateau(p, a, *best, r);
    slide(p, a, *best, r);  // off with trust.slide_range_mm = 0
    if (s.policies.polish) polish(p, *best, r);
    if (s.policies.rivals) reject_rivals(p, a, *best, r);
    if (s.policies.confirm) require_confirmation(p, a, *best, r);
    if (s.policies.consistent) require_consistent_residuals(p, r);  // refine-only
    if (s.policies.twins) probe_twins(p, *best, r);
    check_pinned(s.trust, r);  // the block jackknife: off with trust.jackknife_blocks = 0
  }
  const auto sl = r.timings_s.find("slide");
  r.timings_s["assess"] = since(t) - (sl == r.timings_s.end() ? 0.0 : sl->second);
  return r;
}

RegistrationResult register_scan(const PointCloud& scan, const PointCloud& ref,
                                 const RegistrationSettings& s, const ViewSampler& view) {
  const auto t = Clock::now();
  check_scale(scan, ref);
  if (s.segment.enabled && s.segment.max_clusters < 1)
    throw Error("segment.max_clusters must be at least 1");
  RegistrationResult r = s.segment.enabled
                             ? register_in_view(scan, ref, view, s, s.segment.max_clusters)
                             : register_cloud(scan, ref, s);
  r.timings_s["total"] = since(t);  // the whole call; the stages above do not cover all of it
  return r;
}

void check_inputs(const PointCloud& scan, const PointCloud& ref, const RegistrationSettings& s) {
  auto finite = [](const PointCloud& c) {
    size_t n = 0;
    for (const auto& p : c.points) n += p.allFinite();
    return n;
  };
  if (finite(scan) < 10) throw Error("scan has no usable points (empty or all NaN)");
  if (finite(ref) < 10) throw Error("reference cloud has no usable points");
  check_slide_settings(s.trust);
}

namespace {

double diagonal(const PointCloud& c) {  // of the finite points' bounding box, mm
  Eigen::AlignedBox3f box;
  for (const auto& p : c.points)
    if (p.allFinite()) box.extend(p);
  return box.isEmpty() ? 0.0 : double(box.diagonal().norm());
}

}  // namespace

// A scan in metres read as millimetres is 1000x smaller than its reference, one in micrometres
// 1000x larger; either would "register" to nonsense. In the project's benchmarks (registration,
// needle, usb, taskboard, stress) the reference's diagonal is 0.27 to 1.9 times the scan's; the
// bounds leave room for a partial view of a large part (30x) and a 30 cm sweep around a 1 mm part
// (300x).
void check_scale(const PointCloud& scan, const PointCloud& ref) {
  constexpr double kRefOverScan = 30, kScanOverRef = 300;
  const double ds = diagonal(scan), dr = diagonal(ref);
  if (!(ds > 0 && dr > 0)) return;  // empty or a single point: check_inputs names it
  if (dr > kRefOverScan * ds || ds > kScanOverRef * dr)
    throw Error("the scan spans " + fmt(ds) + " mm and the reference " + fmt(dr) +
                " mm (bounding-box diagonals, " + fmt(std::max(ds / dr, dr / ds)) +
                "x apart): not the same unit? (a cloud that does not state its unit is read in "
                "--unit, mm by default)");
}

const char* status_name(Status s) {
  switch (s) {
    case Status::Ok:
      return "ok";
    case Status::Ambiguous:
      return "ambiguous";
    case Status::Failed:
      return "failed";
  }
  return "?";
}

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

std::string fmt_t(const Pose& T) {
  return "t = [" + fmt(T.translation().x()) + ", " + fmt(T.translation().y()) + ", " +
         fmt(T.translation().z()) + "]";
}

}  // namespace laserfit::registration
