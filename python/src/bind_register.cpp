// laserfit.register and its result: the same register_scan and settings as `laserfit register`.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "laserfit/core/enum_names.hpp"
#include "laserfit/core/units.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/registration/registration.hpp"
#include "laserfit/registration/thresholds.hpp"

namespace laserfit::python {
namespace {

namespace reg = registration;

// A cloud argument: a path (read in `unit` unless the file states its own) or an array.
PointCloud cloud_arg(const py::object& o, const std::string& what, Unit unit) {
  if (py::isinstance<py::str>(o)) return io::read_cloud(o.cast<std::string>(), unit);
  if (!py::isinstance<py::array>(o)) throw py::type_error(what + ": expected an array or a path");
  return cloud_from_array(o.cast<py::array>(), what, unit_to_mm(unit));
}

struct Request {
  py::object scan, ref, ref_normals, scan_normals, sensor_origin, prior, q0;
  bool refine_only = false, segment = true;
  std::string method, thresholds, object, unit;
  uint64_t seed = 1;
};

reg::RegistrationResult run(const Request& q) {
  const Unit unit = parse_unit(q.unit);
  PointCloud scan = cloud_arg(q.scan, "scan", unit);
  PointCloud ref = cloud_arg(q.ref, "ref", unit);
  if (!q.scan_normals.is_none())
    set_normals(scan, q.scan_normals.cast<py::array>(), "scan_normals");
  if (!q.ref_normals.is_none()) set_normals(ref, q.ref_normals.cast<py::array>(), "ref_normals");
  if (!ref.has_normals()) throw py::value_error("ref: the reference needs normals (ref_normals)");
  reg::RegistrationSettings s;
  reg::apply_method(s, q.method.empty() ? reg::Method::Ceres : parse_enum<reg::Method>(q.method));
  s.seed = q.seed;
  s.segment.enabled = q.segment;
  if (!q.prior.is_none()) {
    s.prior = pose_from_array(q.prior.cast<py::array>(), "prior", unit_to_mm(unit));
    s.skip_coarse = q.refine_only;
  } else if (q.refine_only) {
    throw py::value_error("refine_only needs a prior");
  }
  if (!q.q0.is_none()) {  // the paper's q0: the orientation the rho_rot gate measures from
    const auto v = q.q0.cast<std::vector<double>>();
    const Eigen::Vector4d w =
        v.size() == 4 ? Eigen::Vector4d(v[0], v[1], v[2], v[3]) : Eigen::Vector4d::Zero();
    if (!(std::abs(w.norm() - 1) <= 1e-3))
      throw py::value_error("q0: expected a unit quaternion (w, x, y, z)");
    s.q0 = Eigen::Quaterniond(w[0], w[1], w[2], w[3]).normalized();
  }
  if (!q.sensor_origin.is_none())
    scan.sensor_origin = vector3_from(q.sensor_origin, "sensor_origin", unit_to_mm(unit));
  if (scan.sensor_origin) s.pre.use_viewpoint = true, s.pre.viewpoint = *scan.sensor_origin;
  if (!q.thresholds.empty()) {  // as `register --thresholds`: tuned values; a method given wins
    reg::load_thresholds(q.thresholds).apply(s, q.object);
    if (!q.method.empty()) reg::apply_method(s, parse_enum<reg::Method>(q.method));
  }
  py::gil_scoped_release release;  // the registration is C++ only from here
  return reg::register_scan(scan, ref, s);
}

}  // namespace

void bind_register(py::module_& m) {
  py::class_<reg::RegistrationResult>(m, "RegistrationResult",
                                      "A registration: pose, trust status and fit statistics (mm)")
      .def_property_readonly(
          "T_scan_ref", [](const reg::RegistrationResult& r) { return pose_array(r.T_scan_ref); },
          "4 x 4: maps reference coordinates into the scan frame (mm)")
      .def_property_readonly(
          "status",
          [](const reg::RegistrationResult& r) { return std::string(reg::status_name(r.status)); },
          "'ok', 'ambiguous' or 'failed'")
      .def_readonly("reason", &reg::RegistrationResult::reason)
      .def_readonly("fitness_mm2", &reg::RegistrationResult::fitness_mm2)
      .def_readonly("inlier_rmse_mm", &reg::RegistrationResult::inlier_rmse_mm)
      .def_readonly("residual_sigma_mm", &reg::RegistrationResult::residual_sigma_mm)
      .def_readonly("overlap", &reg::RegistrationResult::overlap)
      .def_readonly("attempts", &reg::RegistrationResult::attempts)
      .def_readonly("sigma_origin_mm", &reg::RegistrationResult::sigma_origin_mm)
      .def_readonly("sigma_rotation_deg", &reg::RegistrationResult::sigma_rotation_deg)
      .def_readonly("part", &reg::RegistrationResult::part)
      .def_readonly("timings_s", &reg::RegistrationResult::timings_s)
      .def_readonly("log", &reg::RegistrationResult::log)
      .def_property_readonly(
          "covariance",
          [](const reg::RegistrationResult& r) {
            py::array_t<double> a({6, 6});
            for (int i = 0; i < 6; ++i)
              for (int j = 0; j < 6; ++j) a.mutable_at(i, j) = r.covariance(i, j);
            return a;
          },
          "6 x 6, [rx ry rz (rad, about the matched points' centroid), tx ty tz (mm)]")
      .def("__repr__", [](const reg::RegistrationResult& r) {
        return "<RegistrationResult " + std::string(reg::status_name(r.status)) +
               (r.reason.empty() ? "" : " (" + r.reason + ")") + ">";
      });

  m.def(
      "register",
      [](py::object scan, py::object ref, py::object ref_normals, py::object scan_normals,
         py::object sensor_origin, py::object prior, py::object q0, bool refine_only,
         std::string method, std::string thresholds, std::string object, uint64_t seed,
         bool segment, std::string unit) {
        return run({scan, ref, ref_normals, scan_normals, sensor_origin, prior, q0, refine_only,
                    segment, method, thresholds, object, unit, seed});
      },
      py::arg("scan"), py::arg("ref"), py::kw_only(), py::arg("ref_normals") = py::none(),
      py::arg("scan_normals") = py::none(), py::arg("sensor_origin") = py::none(),
      py::arg("prior") = py::none(), py::arg("q0") = py::none(), py::arg("refine_only") = false,
      py::arg("method") = "", py::arg("thresholds") = "", py::arg("object") = "",
      py::arg("seed") = 1, py::arg("segment") = true, py::arg("unit") = "mm",
      "The pose of `ref` in `scan` (laserfit register): Algorithm 1 and laserfit's trust rules.\n"
      "scan, ref: N x 3 / H x W x 3 arrays or PCD/PLY paths; ref needs normals (ref_normals or\n"
      "the file's). prior: the arm's 4 x 4 T_scan_ref (refine_only: no RANSAC); q0: the\n"
      "orientation (w, x, y, z) the rho_rot gate keeps RANSAC near. method: ceres\n"
      "(default), paper, point_to_point, point_to_plane, gicp, ndt. unit: of arrays,\n"
      "unit-less files, prior and sensor_origin. thresholds: a `laserfit tune` file, `object`\n"
      "naming the entry to use. The GIL is released while it works.");
}

}  // namespace laserfit::python
