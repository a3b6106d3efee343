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

// The target's extent across the insertion axis (insertion frame, mm): where its face stops a part.
Eigen::AlignedBox2d face_extent(const CellSettings& s) {
  const auto& mesh = s.scene.objects[s.target].mesh;
  const Pose to_insertion = s.T_target_part_insert.inverse();
  Eigen::AlignedBox2d box;
  for (const auto& v : mesh.vertices) box.extend((to_insertion * v.cast<double>()).head<2>());
  return box;
}

bool blocked(const CellSettings& s, const Eigen::AlignedBox2d& face, const Insertion& at) {
  const bool in_hole =
      std::abs(at.x_mm) <= s.clearance.x_mm && std::abs(at.y_mm) <= s.clearance.y_mm;
  return at.depth_mm > s.clearance.depth_mm && !in_hole &&
         face.contains(Eigen::Vector2d(at.x_mm, at.y_mm));
}

}  // namespace

std::optional<Contact> first_contact(const CellSettings& s, const Pose& T_world_target,
                                     const Pose& from, const Pose& to, double step_mm) {
  if (s.target < 0 || s.scene.objects[s.target].mesh.vertices.empty()) return std::nullopt;
  const Eigen::AlignedBox2d face = face_extent(s);
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
    if (blocked(s, face, at) && at.depth_mm > start_depth) return Contact{last, f * length, at};
    last = p;
  }
  return std::nullopt;
}

}  // namespace laserfit::cell
