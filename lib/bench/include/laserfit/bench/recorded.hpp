#pragma once
// Recorded scenes: a lab's own scans with externally measured ground truth, scored exactly as
// simulated ones. The ground truth uses BOP's scene_gt.json (Hodan et al., BOP challenge): per
// image id a list of {obj_id, cam_R_m2c (3x3, row-major), cam_t_m2c (mm)}. BOP's camera is the
// scan's frame here, so each entry is T_scan_object. docs/benchmark.md describes the folder.
#include <map>
#include <string>

#include "laserfit/bench/trial.hpp"
#include "laserfit/core/pose.hpp"

namespace laserfit::bench {

// image id -> obj_id -> T_scan_object (mm).
using PoseTable = std::map<int, std::map<int, Pose>>;

// Throws laserfit::Error naming the file: not BOP's layout, a non-numeric image id, an obj_id
// twice in one image, a rotation that is not one (BOP files hold rounded floats: ||R R^T - I||
// up to 1e-3 is re-orthonormalised), a non-finite number.
PoseTable read_scene_gt(const std::string& path);
// Full double precision, so that reading it back gives the same poses bit for bit.
void write_scene_gt(const std::string& path, const PoseTable& poses);

// scans/<id as 6 digits>.pcd, else .ply, in a recorded folder; throws naming the first if neither.
std::string recorded_scan_path(const std::string& dir, int image_id);

// A recorded scene's references and models (see PreparedScene); its poses are the SceneCase's.
PreparedScene prepare_recorded(const SceneCase& sc, uint64_t seed);
// Trial t's scan and poses: truth from scene_gt.json, prior from scene_prior.json if there is one.
TrialInput recorded_trial(const SceneCase& sc, const PreparedScene& p, const Trial& t);

}  // namespace laserfit::bench

namespace laserfit::bench {

struct ExportSummary {
  size_t trials = 0, objects = 0;
  double wall_s = 0;
};

// A simulated benchmark's scans as recorded scenes in BOP's layout, the form a lab's own dataset
// takes (docs/benchmark.md): DIR/benchmark.yaml (laserfit bench runs it), DIR/models/ (each
// target's mesh as obj_<obj_id>.ply, models_info.json with BOP's diameter, extent and
// symmetries), DIR/refs/<scene>_<object>.pcd (the references the benchmark registers against)
// and per scene DIR/<scene>/scene_gt.json, scene_prior.json and scans/<image id>.pcd. The image
// id is the trial's index, so the recorded run registers with the simulated run's seeds.
// `repetitions` / `scenes` select trials as for generate_dataset.
ExportSummary export_bop(const Benchmark& b, const std::string& dir, int jobs = 1,
                         const std::vector<int>& repetitions = {},
                         const std::vector<std::string>& scenes = {});

}  // namespace laserfit::bench
