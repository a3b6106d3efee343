#pragma once
// Slide search: a pose that came back flat along a translation the task did not declare weak is
// refined again from poses slid along that direction, and kept when the data pin it there.
#include <optional>
#include <vector>

#include "stages.hpp"

namespace laserfit::registration {

struct SlideOutcome {
  RegistrationResult result;               // the best pinned re-refinement, assessed
  double offset_mm = 0;                    // where along the flat direction its refinement started
  std::vector<RegistrationResult> pinned;  // every pinned re-refinement, assessed (rivals for the
                                           // agreement checks)
  int iterations = 0;
};

// The flat translation of an ambiguous result that the slide search would search (scan frame,
// unit): its weakest direction is mostly a translation, below the ambiguity ratio, and not along
// the task's declared weak translation (a plug's slide along itself is expected and reported).
std::optional<Eigen::Vector3d> flat_translation(const RegistrationResult& r,
                                                const TrustSettings& t);

// Throws Error unless step and range are >= 0 and the range is at most max_slide_steps steps
// (each step is two refinements, and the regrown crop spans the range).
constexpr int max_slide_steps = 64;
void check_slide_settings(const TrustSettings& t);

// `slid`: the assessed ambiguous result; `base`: the refinement input (its init is ignored). The
// starts cover slid's plateau (flat_from_mm .. flat_to_mm) and the slide range beyond it, at most
// max_slide_steps on either side.
std::optional<SlideOutcome> slide_search(const RefineInput& base, const Matcher& m,
                                         const TrustSettings& t, const RegistrationResult& slid);

}  // namespace laserfit::registration
