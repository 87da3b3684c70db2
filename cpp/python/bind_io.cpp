// Hair files by path (hairlod/io/hair_file.h). Reads and writes release the GIL.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "hairlod/io/hair_file.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {

using FormatList = std::vector<std::pair<std::string, std::string>>;

FormatList format_list(bool writable_only) {
    FormatList formats;
    for (const io::HairFormatInfo& info : io::hair_formats())
        if (info.writable || !writable_only)
            formats.emplace_back(std::string(info.extension), std::string(info.description));
    return formats;
}

}  // namespace

void bind_io(py::module_& m) {
    m.def(
        "read_hair_file",
        [](const std::filesystem::path& path, std::optional<float> default_radius) {
            return io::read_hair_file(path, io::ReadOptions{default_radius}).strands;
        },
        py::arg("path"), py::arg("default_radius") = py::none(),
        py::call_guard<py::gil_scoped_release>(),
        R"doc(Reads a .hair, .data, .bin, .ply or .tfx file (format from the extension) into Strands.

default_radius: radius for formats that store no thickness (.data, .bin, .tfx, .ply without a
radius property); None means 1e-4 times the bounding-box diagonal of the points.
Raises HairlodError (a ValueError) naming the file and the problem.)doc");
    m.def("write_hair_file", &io::write_hair_file, py::arg("path"), py::arg("strands"),
          py::call_guard<py::gil_scoped_release>(),
          R"doc(Writes Strands to a .hair or .data file through a temporary file renamed when
complete; on error no file is left. Raises HairlodError naming the file and the problem.)doc");
    m.def(
        "hair_read_formats", [] { return format_list(false); },
        "List of (extension, description) of the hair file formats read_hair_file reads.");
    m.def(
        "hair_write_formats", [] { return format_list(true); },
        "List of (extension, description) of the hair file formats write_hair_file writes.");
}

}  // namespace hairlod::python
