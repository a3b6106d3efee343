// Why: a part whose only feature along its length is a hole (a needle's eye) is matched from the
// scan side only (trust.cpp), and a hole is an absence of scan points. With the reference slid so
// far that its eye lies where the scan has no data (beyond the sensor's last column, or in a
// thread's shadow), the scan's eye faces plain shaft and nothing penalises it: the fit is flat
// along the shaft and the refinement stops anywhere on the plateau (in a controller campaign,
// 1.3 mm off). A refinement started near the true slide falls into the eye's edges and is pinned;
// so the plateau is searched by restarts, not by a smarter local step.
#include "slide.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "laserfit/core/error.hpp"

namespace laserfit::registration {

std::optional<Eigen::Vector3d> flat_translation(const RegistrationResult& r,
                                                const TrustSettings& t) {
  const Vector6d& d = r.weakest_direction;
  if (r.status != Status::Ambiguous || r.flat == 0 || d.tail<3>().norm() <= d.head<3>().norm())
    return std::nullopt;
  const Eigen::Vector3d axis = d.tail<3>().normalized();
  if (t.weak_translation &&
      std::abs(axis.dot(r.T_scan_ref.rotation() * *t.weak_translation)) > std::cos(M_PI / 18))
    return std::nullopt;
  return axis;
}

void check_slide_settings(const TrustSettings& t) {
  if (!(t.slide_step_mm >= 0) || !(t.slide_range_mm >= 0) ||
      (t.slide_step_mm > 0 && t.slide_range_mm > max_slide_steps * t.slide_step_mm))
    throw Error("slide search: step " + std::to_string(t.slide_step_mm) + " mm, range " +
                std::to_string(t.slide_range_mm) + " mm: both must be >= 0, the range at most " +
                std::to_string(max_slide_steps) + " steps");
}

std::optional<SlideOutcome> slide_search(const RefineInput& base, const Matcher& m,
                                         const TrustSettings& t, const RegistrationResult& slid) {
  if (t.slide_step_mm <= 0 || t.slide_range_mm < t.slide_step_mm) return std::nullopt;
  const auto flat_axis = flat_translation(slid, t);
  if (!flat_axis) return std::nullopt;
  const Eigen::Vector3d axis = *flat_axis;

  // Starts one step apart: one of them is within half a step of the pinned pose, so a gate of one
  // step reaches it. A start on the plateau would only crawl along it (no gradient there), so the
  // iterations are capped; a start that reaches the eye's edges converges in a few.
  RefineSettings fast = base.s;
  fast.initial_gate_mm = t.slide_step_mm, fast.max_iterations = std::min(fast.max_iterations, 15);
  // The starts are independent: refined in parallel, stored by index, chosen in order (the same
  // pose whatever the thread count).
  auto steps = [&](double reach) {
    return std::min(max_slide_steps,
                    int(std::floor((t.slide_range_mm + reach) / t.slide_step_mm + 1e-9)));
  };
  const int ahead = steps(std::max(0.0, slid.flat_to_mm)),
            behind = steps(std::max(0.0, -slid.flat_from_mm));
  std::vector<double> offsets;
  for (int k = 1; k <= std::max(ahead, behind); ++k) {
    if (k <= ahead) offsets.push_back(k * t.slide_step_mm);
    if (k <= behind) offsets.push_back(-k * t.slide_step_mm);
  }
  std::vector<RegistrationResult> found(offsets.size());
  std::vector<int> iterations(offsets.size(), 0);
  tbb::parallel_for(size_t(0), offsets.size(), [&](size_t i) {
    const Pose init = Eigen::Translation3d(offsets[i] * axis) * slid.T_scan_ref;
    const RefineInput in{base.ref, base.scan,  base.scan_tree, base.ref_tree,
                         init,     base.voxel, fast,           base.oriented};
    const RefineOutput o = refine_ceres(in);
    iterations[i] = o.iterations;
    found[i].status = Status::Failed;
    if (!o.T.matrix().allFinite()) return;
    found[i].T_scan_ref = o.T;
    assess(*base.scan, *base.ref_tree, m, t, base.voxel, found[i]);
  });
  std::optional<SlideOutcome> out;
  std::vector<RegistrationResult> pinned;
  int total = 0;
  for (size_t i = 0; i < offsets.size(); ++i) {
    const RegistrationResult& x = found[i];
    total += iterations[i];
    // Pinned: fewer flat directions than the slid pose, and as good a fit of as much of the
    // scan, not a pose that explains less of it.
    if (x.status == Status::Failed || x.flat >= slid.flat) continue;
    if (!fits_as_well(x, slid)) continue;
    pinned.push_back(x);
    if (!out || x.fitness_mm2 < out->result.fitness_mm2) out = SlideOutcome{x, offsets[i], {}, 0};
  }
  if (out) out->pinned = std::move(pinned), out->iterations = total;
  return out;
}

}  // namespace laserfit::registration
