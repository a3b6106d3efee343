// Recorded scenes: BOP's scene_gt.json in and out, and a lab's scans as benchmark trials.
#include "laserfit/bench/recorded.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "laserfit/cad/import.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/sampling/sampling.hpp"

namespace laserfit::bench {
namespace fs = std::filesystem;

namespace {

int image_id(const std::string& path, const std::string& key) {
  const bool digits =
      !key.empty() && key.size() <= 9 && key.find_first_not_of("0123456789") == std::string::npos;
  if (!digits)
    throw Error(path, "image id '" + key.substr(0, 40) + "' is not a number 0..999999999");
  return std::stoi(key);
}

// One BOP entry as T_scan_object. BOP files round to float precision, so a rotation within 1e-3
// of orthonormal is projected onto the nearest one (SVD); an exact one is kept bit for bit.
Pose bop_pose(const std::string& path, const io::Json& e, const std::string& where) {
  const auto r = e.at("cam_R_m2c").get<std::vector<double>>();
  const auto t = e.at("cam_t_m2c").get<std::vector<double>>();
  if (r.size() != 9 || t.size() != 3)
    throw Error(path, where + ": cam_R_m2c needs 9 numbers, cam_t_m2c 3");
  Pose T = Pose::Identity();
  Eigen::Matrix3d R;
  for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = r[i];
  T.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  const double off = (R * R.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (!R.allFinite() || !T.translation().allFinite() || !(off <= 1e-3) || R.determinant() <= 0)
    throw Error(path, where + ": cam_R_m2c is not a rotation (or a number is not finite)");
  if (off > 1e-12) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    R = svd.matrixU() * svd.matrixV().transpose();
  }
  T.linear() = R;
  return T;
}

TriMesh read_mesh(const std::string& path, Unit unit) {
  cad::ImportSettings s;
  s.unit = unit;
  return cad::import_cad(path, s).mesh;
}

}  // namespace

PoseTable read_scene_gt(const std::string& path) {
  const io::Json j = io::read_json(path);
  if (!j.is_object())
    throw Error(path, "not BOP's scene_gt layout: expected {\"<image id>\": [{obj_id, ...}]}");
  PoseTable table;
  try {
    for (const auto& [key, list] : j.items()) {
      const int id = image_id(path, key);
      if (!list.is_array()) throw Error(path, "image " + key + ": expected a list of objects");
      auto& image = table[id];
      for (const auto& e : list) {
        if (!e.is_object() || !e.contains("obj_id") || !e.at("obj_id").is_number_integer())
          throw Error(path, "image " + key + ": every entry needs an integer obj_id");
        const int obj = e.at("obj_id").get<int>();
        const std::string where = "image " + key + ", obj_id " + std::to_string(obj);
        if (!image.emplace(obj, bop_pose(path, e, where)).second)
          throw Error(path, where + " is listed twice (laserfit scores one instance per object)");
      }
    }
  } catch (const io::Json::exception& e) {
    throw Error(path, std::string("not BOP's scene_gt layout: ") + e.what());
  }
  if (table.empty()) throw Error(path, "lists no image");
  return table;
}

void write_scene_gt(const std::string& path, const PoseTable& poses) {
  std::string text = "{";  // one line per image, as the BOP toolkit writes it
  for (const auto& [id, objects] : poses) {
    io::Json list = io::Json::array();
    for (const auto& [obj, T] : objects) {
      std::vector<double> r, t;
      for (int i = 0; i < 9; ++i) r.push_back(T.linear()(i / 3, i % 3));
      for (int i = 0; i < 3; ++i) t.push_back(T.translation()[i]);
      list.push_back({{"cam_R_m2c", r}, {"cam_t_m2c", t}, {"obj_id", obj}});
    }
    text += (text.size() > 1 ? ",\n \"" : "\n \"") + std::to_string(id) + "\": " + list.dump();
  }
  write_file_atomic(path, text + "\n}\n");
}

std::string recorded_scan_path(const std::string& dir, int image_id) {
  char name[32];
  std::snprintf(name, sizeof name, "/scans/%06d", image_id);
  const std::string pcd = dir + name + ".pcd", ply = dir + name + ".ply";
  std::error_code ec;
  if (!fs::is_regular_file(pcd, ec) && fs::is_regular_file(ply, ec)) return ply;
  return pcd;  // read_cloud names it if it is missing
}

PreparedScene prepare_recorded(const SceneCase& sc, uint64_t seed) {
  PreparedScene p;
  for (const auto& t : sc.targets) {
    const TriMesh mesh =
        t.reference_mesh.empty() ? TriMesh{} : read_mesh(t.reference_mesh, sc.unit);
    if (t.reference == ReferenceSource::Cloud) {
      p.reference.push_back(io::read_cloud(t.reference_cloud, sc.unit));
    } else {  // full: sampled from the mesh as a simulated scene's would be
      sampling::SamplingSettings ss;
      ss.count = t.reference_points, ss.seed = seed;
      p.reference.push_back(sampling::sample_uniform(mesh, ss));
    }
    if (p.reference.back().points.empty())
      throw Error(t.reference_cloud.empty() ? t.reference_mesh : t.reference_cloud,
                  "the reference of '" + t.object + "' has no points");
    p.reference_mesh.push_back(mesh);
    p.object.push_back(t.label);
    p.model.push_back(t.model.empty() ? p.reference.back().points
                                      : read_mesh(t.model, sc.unit).vertices);
    p.pivot.push_back(Eigen::Vector3d::Zero());
  }
  return p;
}

namespace {

const Pose& pose_in(const PoseTable& table, const std::string& file, int image, const Target& t) {
  const auto im = table.find(image);
  if (im == table.end()) throw Error(file, "has no image " + std::to_string(image));
  const auto it = im->second.find(t.obj_id);
  if (it == im->second.end())
    throw Error(file, "image " + std::to_string(image) + " has no obj_id " +
                          std::to_string(t.obj_id) + " ('" + t.object + "')");
  return it->second;
}

// Poses in the wrong unit (a scene_gt.json in metres) put the part nowhere near the scan: refuse
// a truth that places the reference's centre farther from the scan's box than the reference's
// own size, rather than score every registration as a miss.
void check_placement(const std::string& file, const Eigen::AlignedBox3d& box, const PointCloud& ref,
                     const Pose& T, const std::string& object) {
  Eigen::AlignedBox3d rbox;
  for (const auto& q : ref.points) rbox.extend(q.cast<double>());
  const double d = box.exteriorDistance(T * rbox.center());
  if (!box.isEmpty() && d > rbox.diagonal().norm())
    throw Error(file, "the ground truth puts '" + object + "' " + std::to_string(int(d)) +
                          " mm from the scan (poses in mm, as in BOP; is the unit right?)");
}

}  // namespace

TrialInput recorded_trial(const SceneCase& sc, const PreparedScene& p, const Trial& t) {
  TrialInput in;
  const std::string scan = recorded_scan_path(sc.recorded_dir, t.image);
  in.scan = io::read_cloud(scan, sc.unit);
  Eigen::AlignedBox3d box;  // of the valid points
  for (const auto& q : in.scan.points)
    if (q.allFinite()) ++in.scan_points, box.extend(q.cast<double>());
  if (in.scan_points == 0) throw Error(scan, "has no valid point");
  const std::string gt = sc.recorded_dir + "/scene_gt.json",
                    pr = sc.recorded_dir + "/scene_prior.json";
  in.has_prior = sc.has_prior && sc.use_prior;
  for (size_t k = 0; k < sc.targets.size(); ++k) {
    in.truth.push_back(pose_in(sc.truth, gt, t.image, sc.targets[k]));
    in.prior.push_back(in.has_prior ? pose_in(sc.prior, pr, t.image, sc.targets[k])
                                    : Pose::Identity());
    check_placement(gt, box, p.reference[k], in.truth[k], sc.targets[k].object);
  }
  return in;
}

}  // namespace laserfit::bench
