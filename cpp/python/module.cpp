// hairlod._core: thin bindings over the C++ core, one bind_<module>.cpp per module.
#include <pybind11/pybind11.h>

#include <exception>
#include <string_view>

#include "bindings.h"
#include "hairlod/core/error.h"

PYBIND11_MODULE(_core, m) {
    m.doc() = "hairlod C++ core";
    static pybind11::exception<hairlod::Error> error_type(m, "HairlodError", PyExc_ValueError);
    pybind11::register_exception_translator([](std::exception_ptr raised) {
        try {
            if (raised) std::rethrow_exception(raised);
        } catch (const hairlod::Error& error) {
            // Messages may quote bytes of a damaged file that are not UTF-8: escape them rather
            // than lose the whole message.
            const std::string_view what = error.what();
            PyObject* text = PyUnicode_DecodeUTF8(what.data(), static_cast<Py_ssize_t>(what.size()), "backslashreplace");
            PyErr_SetObject(error_type.ptr(), text);
            Py_XDECREF(text);
        }
    });
    hairlod::python::bind_core(m);
    hairlod::python::bind_curves(m);
    hairlod::python::bind_io(m);
    hairlod::python::bind_lod(m);
    hairlod::python::bind_bcsdf(m);
    hairlod::python::bind_hairmesh(m);
    hairlod::python::bind_render(m);
}
