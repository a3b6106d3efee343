#pragma once
// The registration accuracy campaign (issue 4): a YAML definition of scenes and targets, random
// pose perturbations, scans from the simulator, registration by every method, symmetry-aware
// errors against the simulator's ground truth. Lengths mm, angles deg.
#include <string>
#include <vector>

#include "laserfit/metrics/pose_error.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/scan/scanner.hpp"

namespace laserfit::campaign {

struct Target {
  std::string object;              // scene object name
  metrics::Symmetry symmetry;
  double voxel_mm = 0;             // 0 = auto
  std::string reference = "view";  // view: what the nominal sweep sees | full: whole surface
  size_t reference_points = 60000;
};

struct SceneCase {
  std::string name, scene_path;
  std::vector<Target> targets;
};

struct Campaign {
  uint64_t seed = 1;
  int trials = 200;
  double rotation_deg = 20;        // true orientation within this of the nominal (= prior q0)
  double translation_mm = 1;       // true position within this of the nominal
  double t_tol_mm = 0.05, r_tol_deg = 0.5;  // success tolerance
  std::vector<SceneCase> scenes;
};
Campaign load_campaign(const std::string& path);  // throws laserfit::Error naming the file

// A method of the comparison: registration settings by name.
// paper: PCL SampleConsensusPrerejective + rho_rot on its result + PCL ICP (Algorithm 1 as
// published); the others: rho_rot inside RANSAC, the arm's prior pose as first hypothesis, and
// the named refiner.
registration::RegistrationSettings method_settings(const std::string& method);

struct Record {
  std::string scene, object, method, status, reason;
  int trial = 0;
  uint64_t seed = 0;
  double t_err_mm = 0, r_err_deg = 0, mssd_mm = 0, time_s = 0;
  size_t scan_points = 0;
  bool success = false, false_accept = false;
};

}  // namespace laserfit::campaign
