#pragma once
// The stages register_cloud (driver.cpp) is built from, in the order it calls them (private to
// lib/registration). Algorithm 1's own stages are in attempts.cpp; the policies laserfit adds for
// its trust decision (settings.hpp, Policies) in policies.cpp. Each stage reads the shared Problem
// and writes its decisions and log lines into the RegistrationResult.
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "reference_cache.hpp"
#include "stages.hpp"

namespace laserfit::registration {

// Everything the stages of one registration share: the prepared clouds, their kd-trees and
// features, built once.
struct Problem {
  explicit Problem(const RegistrationSettings& settings) : s(settings) {}
  const RegistrationSettings& s;
  double voxel = 0;               // mm
  PclCloud::Ptr scan, ref;        // filtered scan; reference with exact normals
  Tree::Ptr scan_tree, ref_tree;  // over scan and ref
  PclCloud::Ptr scan_c, ref_c;    // the coarser grid of the RANSAC stage ...
  Features::Ptr scan_f, ref_f;    // ... and its FPFH (null without a coarse stage)
  Matcher matcher;                // the refinement's correspondence gate
  RefineFn refine = nullptr;      // s.refine.method
  bool coarse = true;             // false: refine the prior only (skip_coarse)
  std::shared_ptr<const PreparedReference> prepared;  // what ref, ref_tree ... came from
  RefineInput refine_input(const Pose& T_scan_ref_init) const {
    return {ref, scan, scan_tree, ref_tree, T_scan_ref_init, voxel, s.refine, s.pre.use_viewpoint};
  }
};

struct Candidate {  // a refined pose and its fit
  Pose T_scan_ref;
  Fit fit;
};
struct Attempts {
  std::vector<Candidate> good;       // refined poses with fitness below rho_ICP
  std::vector<Candidate> converged;  // every refined pose inside the rho_rot cone
};

// Seconds since a time point (the per-stage timings of RegistrationResult).
using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
std::string fmt(double v);         // %.4g, for log lines
std::string fmt_t(const Pose& T);  // "t = [x, y, z]"

// Throws Error on clouds without usable points and on settings out of range.
void check_inputs(const PointCloud& scan, const PointCloud& ref, const RegistrationSettings& s);
// Refuses a scan and a reference whose extents differ by a unit's factor (Error names both).
void check_scale(const PointCloud& scan, const PointCloud& ref);

// A copy of a scan without its mixed pixels, and the seconds that took (segmented.cpp).
struct CleanedScan {
  PointCloud scan;
  double seconds = 0;
};
CleanedScan clean_scan(const PointCloud& scan);
// register_segmented on a cleaned scan, its cleaning counted in t_clean seconds of segmentation:
// register_in_view registers one scan twice.
RegistrationResult register_cleaned(const PointCloud& scan, double t_clean, const PointCloud& ref,
                                    const RegistrationSettings& s, int max_clusters,
                                    int* cluster = nullptr);

// Algorithm 1, line 1 and the features of line 4 (attempts.cpp).
Problem prepare_problem(const PointCloud& scan, const PointCloud& ref,
                        const RegistrationSettings& s, RegistrationResult& r);
// Lines 2-8: RANSAC hypotheses (the prior first), the d_phi gate, refinement, until two refined
// poses agree or the attempts run out.
Attempts run_attempts(const Problem& p, RegistrationResult& r);
// Line 9: the attempt to keep, assessed (trust.cpp); nullopt (r failed) when none converged.
std::optional<Candidate> keep_best(const Problem& p, const Attempts& a, RegistrationResult& r);
// Two poses agree when they place the reference's surface in the same place.
bool agree(const Pose& a, const Pose& b, const PclCloud& ref, const TrustSettings& t);
Candidate candidate(const RegistrationResult& r);  // an assessed pose as a candidate

// The policies (policies.cpp), each a no-op where it does not apply.
void prefer_prior(const Problem& p, const Attempts& a, Candidate& best, RegistrationResult& r);
void measure_plateau(const Problem& p, const Attempts& a, const Candidate& best,
                     RegistrationResult& r);
void slide(const Problem& p, Attempts& a, Candidate& best, RegistrationResult& r);
void polish(const Problem& p, const Candidate& best, RegistrationResult& r);
void reject_rivals(const Problem& p, const Attempts& a, const Candidate& best,
                   RegistrationResult& r);
void require_confirmation(const Problem& p, const Attempts& a, const Candidate& best,
                          RegistrationResult& r);
void require_consistent_residuals(const Problem& p, RegistrationResult& r);
// twins.cpp: an ok pose turned by each near-symmetry of the reference and refined; one the scan
// does not tell apart from it -> ambiguous, one it clearly prefers replaces it.
void probe_twins(const Problem& p, Candidate& best, RegistrationResult& r);

}  // namespace laserfit::registration
