// hairlod._core: thin bindings over the C++ core, one bind_<module>.cpp per module.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "hairlod/core/error.h"

PYBIND11_MODULE(_core, m) {
    m.doc() = "hairlod C++ core";
    pybind11::register_exception<hairlod::Error>(m, "HairlodError", PyExc_ValueError);
    hairlod::python::bind_core(m);
    hairlod::python::bind_io(m);
    hairlod::python::bind_lod(m);
    hairlod::python::bind_bcsdf(m);
    hairlod::python::bind_hairmesh(m);
    hairlod::python::bind_render(m);
}
