#pragma once
#include <pybind11/pybind11.h>

namespace hairlod::python {

void bind_core(pybind11::module_& m);
void bind_curves(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_hairmesh(pybind11::module_& m);
void bind_lod(pybind11::module_& m);
void bind_bcsdf(pybind11::module_& m);
void bind_render(pybind11::module_& m);

}  // namespace hairlod::python
