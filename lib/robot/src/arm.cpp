#include "laserfit/robot/arm.hpp"

#include <Eigen/Geometry>

namespace laserfit::robot {
namespace {

Pose dh(const DhRow& r, double q) {
  Pose T = Pose::Identity();
  T.rotate(Eigen::AngleAxisd(r.alpha_rad, Eigen::Vector3d::UnitX()));
  T.translate(Eigen::Vector3d(r.a_mm, 0, 0));
  T.rotate(Eigen::AngleAxisd(q + r.theta_rad, Eigen::Vector3d::UnitZ()));
  T.translate(Eigen::Vector3d(0, 0, r.d_mm));
  return T;
}

}  // namespace

ArmModel ArmModel::panda() {
  ArmModel m;
  m.name = "franka_panda";
  const double h = M_PI / 2;
  // a (mm), d (mm), alpha (rad): the official modified-DH table; flange d = 107 mm.
  m.joints = {{{0, 333, 0, 0},
               {0, 0, -h, 0},
               {0, 316, h, 0},
               {82.5, 0, h, 0},
               {-82.5, 384, -h, 0},
               {0, 0, h, 0},
               {88, 0, h, 0}}};
  m.flange = {0, 107, 0, 0};
  auto& L = m.limits;
  L.q_min << -2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973;
  L.q_max << 2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973;
  L.qd_max << 2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100;
  L.qdd_max << 15, 7.5, 10, 12.5, 15, 20, 20;
  L.qddd_max << 7500, 3750, 5000, 6250, 7500, 10000, 10000;
  return m;
}

Pose ArmModel::fk(const Joints& q, std::array<Pose, 8>* frames) const {
  Pose T = Pose::Identity();
  for (int i = 0; i < 7; ++i) {
    T = T * dh(joints[i], q[i]);
    if (frames) (*frames)[i] = T;
  }
  T = T * dh(flange, 0);
  if (frames) (*frames)[7] = T;
  return T;
}

Pose ArmModel::fk(const Joints& q) const { return fk(q, nullptr); }

Jacobian ArmModel::jacobian(const Joints& q) const {
  std::array<Pose, 8> F;
  const Pose T = fk(q, &F);
  Jacobian J;
  for (int i = 0; i < 7; ++i) {
    const Eigen::Vector3d z = F[i].linear().col(2);  // joint i turns about its frame's z
    J.block<3, 1>(0, i) = z.cross(T.translation() - F[i].translation());
    J.block<3, 1>(3, i) = z;
  }
  return J;
}

bool ArmModel::within_limits(const Joints& q, double margin) const {
  return ((q.array() >= limits.q_min.array() + margin) &&
          (q.array() <= limits.q_max.array() - margin))
      .all();
}

}  // namespace laserfit::robot
