// The Python module laserfit._laserfit (python/laserfit/__init__.py re-exports it): reading and
// writing clouds, CAD import, reference clouds, scan synthesis, registration (bind_register.cpp).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "laserfit/cad/import.hpp"
#include "laserfit/core/build_info.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/units.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/sampling/sampling.hpp"
#include "laserfit/scan/scanner.hpp"

namespace laserfit::python {
namespace {

py::dict cloud_dict(const PointCloud& c) {
  py::dict d;
  d["points"] = points_array(c);
  d["normals"] = c.has_normals() ? py::object(vectors_array(c.normals)) : py::none();
  if (!c.labels.empty()) {
    py::array_t<int32_t> l(py::ssize_t(c.labels.size()), c.labels.data());
    if (c.organized()) l.resize({py::ssize_t(c.height), py::ssize_t(c.width)});
    d["labels"] = l;
  } else {
    d["labels"] = py::none();
  }
  d["sensor_origin"] = c.sensor_origin
                           ? py::object(py::make_tuple(c.sensor_origin->x(), c.sensor_origin->y(),
                                                       c.sensor_origin->z()))
                           : py::none();
  d["metadata"] = c.metadata;
  return d;
}

TriMesh mesh_from(const py::array& vertices, const py::array& faces) {
  TriMesh m;
  m.vertices = cloud_from_array(vertices, "vertices", 1.0).points;
  const auto f = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(faces);
  if (!f || f.ndim() != 2 || f.shape(1) != 3) throw py::value_error("faces: expected M x 3");
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      const int64_t v = f.at(i, k);
      if (v < 0 || v >= int64_t(m.vertices.size()))
        throw py::value_error("faces: vertex index " + std::to_string(v) + " out of range");
      t[k] = int(v);
    }
    m.faces.push_back(t);
  }
  return m;
}

void bind_io(py::module_& m) {
  m.def(
      "read_cloud",
      [](const std::string& path, const std::string& unit) {
        return cloud_dict(io::read_cloud(path, parse_unit(unit)));
      },
      py::arg("path"), py::arg("unit") = "mm",
      "A PCD / PLY cloud in mm (float32 points, N x 3 or H x W x 3 when organized), its normals, "
      "labels, sensor origin and header metadata; `unit` for a file that does not state one.");
  m.def(
      "write_cloud",
      [](const std::string& path, const py::array& points, const py::object& normals,
         const py::object& sensor_origin) {
        PointCloud c = cloud_from_array(points, "points", 1.0);
        if (!normals.is_none()) set_normals(c, normals.cast<py::array>(), "normals");
        if (!sensor_origin.is_none())
          c.sensor_origin = vector3_from(sensor_origin, "sensor_origin", 1.0);
        io::write_cloud(path, c);
      },
      py::arg("path"), py::arg("points"), py::arg("normals") = py::none(),
      py::arg("sensor_origin") = py::none(), "Writes a binary PCD / PLY (by extension) in mm.");
}

void bind_cad(py::module_& m) {
  m.def(
      "import_mesh",
      [](const std::string& path, const std::string& unit) {
        cad::ImportSettings s;
        s.unit = parse_unit(unit);
        cad::ImportResult r;
        {
          py::gil_scoped_release release;
          r = cad::import_cad(path, s);
        }
        py::array_t<int32_t> faces({py::ssize_t(r.mesh.faces.size()), py::ssize_t(3)});
        for (size_t i = 0; i < r.mesh.faces.size(); ++i)
          for (int k = 0; k < 3; ++k) faces.mutable_at(i, k) = r.mesh.faces[i][k];
        return py::make_tuple(vectors_array(r.mesh.vertices), faces);
      },
      py::arg("path"), py::arg("unit") = "auto",
      "(vertices N x 3 float32 mm, faces M x 3 int32) of a CAD file (laserfit import: STEP, "
      "IGES, STL, OBJ, PLY, ...), checked and repaired; the parser runs isolated.");
  m.def(
      "refcloud",
      [](const py::array& vertices, const py::array& faces, size_t count, double density,
         uint64_t seed, const py::object& view) {
        const TriMesh mesh = mesh_from(vertices, faces);
        sampling::SamplingSettings s;
        s.count = count, s.density_per_mm2 = density, s.seed = seed;
        if ((count > 0) == (density > 0)) throw py::value_error("give count or density, not both");
        PointCloud c;
        if (view.is_none()) {
          py::gil_scoped_release release;
          c = sampling::sample_uniform(mesh, s);
        } else {
          sampling::ViewSettings v;
          v.T_mesh_sensor.push_back(pose_from_array(view.cast<py::array>(), "view", 1.0));
          py::gil_scoped_release release;
          c = sampling::sample_visible(mesh, v, s);
        }
        return py::make_tuple(points_array(c), vectors_array(c.normals));
      },
      py::arg("vertices"), py::arg("faces"), py::arg("count") = 0, py::arg("density") = 0.0,
      py::arg("seed") = 1, py::arg("view") = py::none(),
      "(points, normals) sampled uniformly over the mesh, or over what a line scanner at `view` "
      "(4 x 4 T_mesh_sensor) sees (laserfit refcloud).");
  m.def(
      "scan",
      [](const std::string& scene, const py::object& seed, bool noise) {
        scan::ScanScene sc = scan::load_scene(scene);
        if (!seed.is_none()) sc.seed = seed.cast<uint64_t>();
        if (!noise) sc.settings.noise.enabled = sc.settings.motion.enabled = false;
        scan::ScanResult r;
        {
          py::gil_scoped_release release;
          r = scan::simulate_scan(sc);
        }
        py::dict d = cloud_dict(r.cloud);
        py::dict truth;
        for (size_t i = 0; i < sc.objects.size(); ++i)
          truth[py::str(sc.objects[i].name)] = pose_array(r.T_scan_object[i]);
        d["T_scan_object"] = truth;
        d["seed"] = r.seed;
        return d;
      },
      py::arg("scene"), py::arg("seed") = py::none(), py::arg("noise") = true,
      "A simulated laser line scan of a scene file (laserfit scan): the organized cloud "
      "(H x W x 3, NaN = no measurement), labels, sensor origin and each object's true pose.");
}

}  // namespace

PYBIND11_MODULE(_laserfit, m) {
  m.doc() = "laserfit's C++ stages (use the package laserfit)";
  m.attr("__version__") = build_info();
  // laserfit::Error (bad input: one line naming the file and the problem) as laserfit.Error.
  py::register_exception<Error>(m, "Error", PyExc_RuntimeError);
  bind_io(m);
  bind_cad(m);
  bind_register(m);
}

}  // namespace laserfit::python
