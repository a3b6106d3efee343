// Registers a box corner (three orthogonal faces pin all six degrees of freedom) moved by a known
// pose, from a prior 0.3 mm / 1 deg off, through laserfit::registration alone. Exit 0 when the
// pose is found within 1 um and 0.001 deg (noise-free points: only the solver's tolerance).
#include <cstdio>

#include "laserfit/registration/registration.hpp"

using namespace laserfit;

int main() {
  PointCloud ref;
  auto face = [&](Eigen::Vector3f o, Eigen::Vector3f u, Eigen::Vector3f v, Eigen::Vector3f n) {
    for (int i = 0; i < 80; ++i)
      for (int j = 0; j < 40; ++j) {
        ref.points.push_back(o + u * (i / 4.f) + v * (j / 4.f));
        ref.normals.push_back(n);
      }
  };
  face({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});  // floor, 20 x 10 mm
  face({0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0});  // wall x = 0
  face({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0});  // wall y = 0
  ref.width = int(ref.points.size());
  const Pose T_true = pose_from_tq(
      {1.0, -2.0, 0.5}, Eigen::Quaterniond(Eigen::AngleAxisd(0.087, Eigen::Vector3d(1, 2, 3).normalized())));
  PointCloud scan = ref;
  scan.normals.clear();
  for (auto& p : scan.points) p = (T_true * p.cast<double>()).cast<float>();
  scan.sensor_origin = T_true * Eigen::Vector3d(30, 30, 60);

  registration::RegistrationSettings s;
  s.segment.enabled = false;
  s.skip_coarse = true;
  s.prior = T_true * pose_from_tq({0.3, 0, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(
                                                  0.017, Eigen::Vector3d::UnitZ())));
  const registration::RegistrationResult r = registration::register_scan(scan, ref, s);
  const Pose d = T_true.inverse() * r.T_scan_ref;
  const double t_um = d.translation().norm() * 1e3;
  const double r_deg = Eigen::AngleAxisd(d.rotation()).angle() * 180 / M_PI;
  std::printf("status %s, %.4f um, %.6f deg from the true pose\n",
              registration::status_name(r.status), t_um, r_deg);
  return t_um < 1.0 && r_deg < 1e-3 ? 0 : 1;
}
