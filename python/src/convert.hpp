#pragma once
// numpy <-> laserfit types. Points arrive as N x 3 or H x W x 3 (organized) float32 / float64
// arrays in a stated unit and leave as float32 millimetres; poses are 4 x 4 float64 arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>

#include "laserfit/core/cloud.hpp"
#include "laserfit/core/pose.hpp"

namespace laserfit::python {

namespace py = pybind11;

// `what` names the argument in errors ("scan", "ref_normals"); to_mm scales points, not normals.
PointCloud cloud_from_array(const py::array& points, const std::string& what, double to_mm);
void set_normals(PointCloud& c, const py::array& normals, const std::string& what);
py::array_t<float> points_array(const PointCloud& c);  // N x 3, or H x W x 3 when organized
py::array_t<float> vectors_array(const std::vector<Eigen::Vector3f>& v);  // N x 3

Pose pose_from_array(const py::array& T, const std::string& what, double to_mm);
py::array_t<double> pose_array(const Pose& T);
Eigen::Vector3d vector3_from(const py::object& v, const std::string& what, double to_mm);

}  // namespace laserfit::python
