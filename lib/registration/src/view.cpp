// Registration against a view reference that follows the pose found (registration.hpp).
#include <cmath>

#include "driver.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::registration {

namespace {

bool has_pose(const RegistrationResult& r) { return r.overlap > 0 && std::isfinite(r.fitness_mm2); }

}  // namespace

RegistrationResult register_in_view(const PointCloud& scan, const PointCloud& ref,
                                    const ViewSampler& view, const RegistrationSettings& s,
                                    int max_clusters) {
  if (!view || !s.policies.view || uses_thin_detector(ref, s))
    return register_segmented(scan, ref, s, max_clusters);
  const CleanedScan cleaned = clean_scan(scan);  // once for both passes
  RegistrationResult first = register_cleaned(cleaned.scan, cleaned.seconds, ref, s, max_clusters);
  if (!has_pose(first)) return first;
  const auto t0 = Clock::now();
  const PointCloud seen = view(first.T_scan_ref);
  const double t_view = since(t0);
  const auto note = [&](RegistrationResult& r, const std::string& line) {
    r.log.push_back(line);
    r.timings_s["view"] = t_view;
  };
  if (seen.points.size() < 10) {
    note(first, "view at the pose found: too few points seen (" +
                    std::to_string(seen.points.size()) + ") -> kept");
    return first;
  }
  // The pose found is the first hypothesis; RANSAC, the rho_rot gate (about the caller's q0, the
  // arm's) and every trust check run again as in any registration.
  RegistrationSettings again = s;
  again.prior = first.T_scan_ref;
  RegistrationResult second;
  try {
    second = register_cleaned(cleaned.scan, 0, seen, again, max_clusters);
  } catch (const Error& e) {
    note(first, std::string("view at the pose found: ") + e.what() + " -> kept");
    return first;
  }
  // The second pass answers unless it lost a pose the first one had: a view sampled at a wrong
  // pose cannot rescue it, and a failed second pass says nothing the first did not.
  const bool keep_first = second.status == Status::Failed && first.status != Status::Failed;
  RegistrationResult& out = keep_first ? first : second;
  std::vector<std::string> log;
  for (const auto& l : first.log) log.push_back("pass 1: " + l);
  log.push_back(std::string("pass 1: ") + status_name(first.status) +
                (first.reason.empty() ? "" : " (" + first.reason + ")") +
                "; reference re-sampled as seen at that pose");
  for (const auto& l : second.log) log.push_back("pass 2: " + l);
  log.push_back(std::string("pass 2: ") + status_name(second.status) +
                (second.reason.empty() ? "" : " (" + second.reason + ")") +
                (keep_first ? " -> pass 1 kept" : " -> kept"));
  std::map<std::string, double> timings = first.timings_s;
  for (const auto& [k, v] : second.timings_s) timings[k] += v;
  out.log = std::move(log), out.timings_s = std::move(timings);
  out.timings_s["view"] = t_view;
  return out;
}

}  // namespace laserfit::registration
