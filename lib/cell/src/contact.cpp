// Contact between the part and the target along a motion. The simulated arms are kinematic: without
// this, an approach with a few mm of error passed the part through the target's face (a USB plug
// 7 mm into the plate, 2.6 mm beside the socket) and the scans showed two solids interpenetrating,
// which no real cell can produce and which registration cannot be asked to explain.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "laserfit/cell/cell.hpp"

namespace laserfit::cell {
namespace {

// The target's extent in the insertion frame (mm): across the axis, where its face stops a part;
// along it, how deep its body reaches (a needle is 0.7 mm thick, a receptacle 12.5 mm deep).
Eigen::AlignedBox3d body_extent(const CellSettings& s) {
  const auto& mesh = s.scene.objects[s.target].mesh;
  const Pose to_insertion = s.T_target_part_insert.inverse();
  Eigen::AlignedBox3d box;
  for (const auto& v : mesh.vertices) box.extend(to_insertion * v.cast<double>());
  return box;
}

bool in_hole(const CellSettings& s, const Insertion& at) {
  return std::abs(at.x_mm) <= s.clearance.x_mm && std::abs(at.y_mm) <= s.clearance.y_mm;
}

// The part's front inside the target's body (past its near face by more than the depth clearance,
// not beyond its far face) where its axis crosses the face outside the hole.
bool blocked(const CellSettings& s, const Eigen::AlignedBox3d& body, const Insertion& at) {
  const bool across = at.x_mm >= body.min().x() && at.x_mm <= body.max().x() &&
                      at.y_mm >= body.min().y() && at.y_mm <= body.max().y();
  return !in_hole(s, at) && across && at.depth_mm > body.min().z() + s.clearance.depth_mm &&
         at.depth_mm <= body.max().z();
}

}  // namespace

std::optional<Contact> first_contact(const CellSettings& s, const Pose& T_world_target,
                                     const Pose& from, const Pose& to, double step_mm,
                                     bool* entered) {
  if (entered) *entered = false;
  if (s.target < 0 || s.scene.objects[s.target].mesh.vertices.empty()) return std::nullopt;
  const Eigen::AlignedBox3d body = body_extent(s);
  const double length = (to.translation() - from.translation()).norm();
  const int n = std::max(1, int(std::ceil(length / step_mm)));
  const Eigen::Quaterniond q0(from.rotation()), q1(to.rotation());
  // A part resting on the face (stopped there, then off by the arm's repeatability) may leave it:
  // only a sample deeper than the start is blocked.
  const double start_depth = check_insertion(s, T_world_target, from).depth_mm;
  Pose last = from;
  for (int k = 1; k <= n; ++k) {
    const double f = double(k) / n;
    Pose p = Pose::Identity();
    p.linear() = q0.slerp(f, q1).toRotationMatrix();
    p.translation() = (1 - f) * from.translation() + f * to.translation();
    const Insertion at = check_insertion(s, T_world_target, p);
    if (in_hole(s, at) && at.depth_mm >= -s.clearance.depth_mm) {
      if (entered) *entered = true;
      return std::nullopt;  // in the hole: its walls guide the part on
    }
    if (blocked(s, body, at) && at.depth_mm > start_depth) return Contact{last, f * length, at};
    last = p;
  }
  return std::nullopt;
}

Pose guided(const CellSettings& s, const Pose& T_world_target, const Pose& T_world_part) {
  const Insertion at = check_insertion(s, T_world_target, T_world_part);
  // Against the wall, a nanometre inside it: rounding must not put a held part beyond it.
  const double wx = s.clearance.x_mm - 1e-6, wy = s.clearance.y_mm - 1e-6;
  const Eigen::Vector3d to_wall(std::clamp(at.x_mm, -wx, wx) - at.x_mm,
                                std::clamp(at.y_mm, -wy, wy) - at.y_mm, 0);
  Pose p = T_world_part;
  p.pretranslate(T_world_target.linear() * s.T_target_part_insert.linear() * to_wall);
  return p;
}

}  // namespace laserfit::cell
