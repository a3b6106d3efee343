#pragma once
// Shared driver for PCL's Registration-derived refiners.
#include "stages.hpp"

namespace laserfit::registration {

// The scan is the source and the dense reference the target, as in the paper's
// ICP(P_scan, P_ref): every scan point has a counterpart on the model, while most of the model is
// unseen and would pull a model-to-scan ICP towards the nearest visible points.
template <typename Reg>
RefineOutput run_pcl_registration(Reg& reg, const RefineInput& in) {
  reg.setInputSource(in.scan);
  reg.setInputTarget(in.ref);
  reg.setSearchMethodTarget(in.ref_tree, true);
  reg.setMaximumIterations(in.s.max_iterations);
  reg.setTransformationEpsilon(in.s.convergence_mm * in.s.convergence_mm);
  PclCloud aligned;
  reg.align(aligned, to_matrix4f(in.init.inverse()));
  RefineOutput out;
  out.T = from_matrix4f(reg.getFinalTransformation()).inverse();  // T_ref_scan -> T_scan_ref
  out.iterations = 0;  // PCL's ICP classes do not report how many iterations they used
  return out;
}

}  // namespace laserfit::registration
