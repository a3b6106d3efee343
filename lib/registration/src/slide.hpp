#pragma once
// Slide search: a pose that came back flat along a translation the task did not declare weak is
// refined again from poses slid along that direction, and kept when the data pin it there.
#include <optional>
#include <vector>

#include "stages.hpp"

namespace laserfit::registration {

struct SlideOutcome {
  RegistrationResult result;  // the best pinned re-refinement, assessed
  double offset_mm = 0;       // where along the flat direction its refinement started
  std::vector<Pose> pinned;   // every pinned re-refinement (rivals for the agreement checks)
  int iterations = 0;
};

// `slid`: the assessed ambiguous result; `base`: the refinement input (its init is ignored).
std::optional<SlideOutcome> slide_search(const RefineInput& base, const Matcher& m,
                                         const TrustSettings& t, const RegistrationResult& slid);

}  // namespace laserfit::registration
