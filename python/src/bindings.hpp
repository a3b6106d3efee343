#pragma once
#include <pybind11/pybind11.h>

namespace laserfit::python {
void bind_register(pybind11::module_& m);
}  // namespace laserfit::python
