// A measurement: register the target and the part in one scan, with the robots' beliefs as priors.
#include <sstream>

#include "laserfit/controller/controller.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::controller {
namespace {

Eigen::Vector3d viewpoint(const PointCloud& scan) {
  std::istringstream in(scan.metadata.count("viewpoint") ? scan.metadata.at("viewpoint") : "");
  Eigen::Vector3d v;
  if (!(in >> v.x() >> v.y() >> v.z())) throw Error("the scan has no laserfit.viewpoint header");
  return v;
}

registration::RegistrationResult register_one(const PointCloud& scan, const PointCloud& ref, const Pose& prior,
                                              const std::string& object, const ControllerSettings& s, uint64_t seed) {
  registration::RegistrationSettings rs;
  s.thresholds.apply(rs, object);
  rs.prior = prior;
  rs.prior_radius_mm = s.prior_radius_mm;
  rs.q0 = Eigen::Quaterniond(prior.rotation());
  rs.pre.use_viewpoint = true, rs.pre.viewpoint = viewpoint(scan);
  rs.seed = seed;
  try {
    return registration::register_segmented(scan, ref, rs, 2);
  } catch (const Error& e) {
    registration::RegistrationResult r;
    r.status = registration::Status::Failed;
    r.reason = e.what();
    return r;
  }
}

}  // namespace

Measurement measure(const PointCloud& scan, const PointCloud& target_ref, const PointCloud& part_ref,
                    const Pose& target_prior, const Pose& part_prior, const cell::CellSettings& cs,
                    const ControllerSettings& s, uint64_t seed, std::vector<std::string>& log) {
  Measurement m;
  const auto& tname = cs.scene.objects[cs.target].name, &pname = cs.scene.objects[cs.part].name;
  m.target = register_one(scan, target_ref, target_prior, tname, s, seed);
  m.part = register_one(scan, part_ref, part_prior, pname, s, seed + 1);
  m.T_scan_target = m.target.T_scan_ref, m.T_scan_part = m.part.T_scan_ref;
  std::string why;
  if (!acceptable(m.target, cs.target_weak_rotation, "", m.T_scan_target, &why)) {
    m.reason = tname + " registration " + why;
  } else if (!acceptable(m.part, "", cs.part_weak_translation, m.T_scan_part, &why)) {
    m.reason = pname + " registration " + why;
  } else {
    m.ok = true;
    m.part_axial_unknown = m.part.status == registration::Status::Ambiguous;
  }
  std::ostringstream l;
  l << "registered " << tname << ": " << registration::status_name(m.target.status) << ", " << pname << ": "
    << registration::status_name(m.part.status) << (m.ok ? " -> accepted" : " -> rejected: " + m.reason);
  log.push_back(l.str());
  return m;
}

}  // namespace laserfit::controller
