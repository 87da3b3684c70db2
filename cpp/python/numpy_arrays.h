#pragma once
// What every binding file needs to pass numpy arrays across: the contiguous array types pybind11
// converts to (forcecast: any numeric dtype is accepted and converted), shape-checked views of
// [N, columns] arrays as glm vectors, and copies of C++ data into new numpy arrays.
#include <pybind11/numpy.h>

#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "hairlod/core/error.h"

namespace hairlod::python {

template <typename T>
using NumpyArray = pybind11::array_t<T, pybind11::array::c_style | pybind11::array::forcecast>;
using FloatArray = NumpyArray<float>;
using DoubleArray = NumpyArray<double>;
using IntArray = NumpyArray<int32_t>;
using Int64Array = NumpyArray<int64_t>;

// The rows of `array` [N, columns] as N items of Row (a glm vector of `columns` floats), without a
// copy: valid while `array` lives. Throws hairlod::Error naming `name` and the shape it got.
template <typename Row>
std::span<const Row> rows_of(const FloatArray& array, int columns, const std::string& name) {
    static_assert(sizeof(Row) % sizeof(float) == 0);
    if (array.ndim() != 2 || array.shape(1) != columns || static_cast<int>(sizeof(Row) / sizeof(float)) != columns)
        throw Error(name + " must have shape [N, " + std::to_string(columns) + "], got " + std::to_string(array.ndim()) +
                    " dimensions" + (array.ndim() == 2 ? " with " + std::to_string(array.shape(1)) + " columns" : ""));
    return {reinterpret_cast<const Row*>(array.data()), static_cast<size_t>(array.shape(0))};
}

// A 4x4 matrix from a numpy [4, 4] array whose rows are the matrix's rows (as Blender's Matrix
// converts); glm stores columns. Throws hairlod::Error naming `what` for another shape.
inline glm::mat4 matrix_from(const FloatArray& m, const char* what) {
    if (m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4) throw Error(std::string(what) + " must be a 4x4 matrix");
    glm::mat4 result;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) result[c][r] = m.at(r, c);
    return result;
}

// A new numpy array of Scalar with `shape`, holding a copy of `values` (T may be a glm vector of
// Scalars); throws hairlod::Error when the shape does not hold exactly that many Scalars.
template <typename Scalar, typename T>
pybind11::array_t<Scalar> to_numpy(const std::vector<T>& values, std::vector<pybind11::ssize_t> shape) {
    pybind11::array_t<Scalar> result(shape);
    if (static_cast<size_t>(result.size()) * sizeof(Scalar) != values.size() * sizeof(T))
        throw Error("to_numpy: the shape does not match the data");
    if (!values.empty()) std::memcpy(result.mutable_data(), values.data(), values.size() * sizeof(T));
    return result;
}

// A new numpy array with `shape`, holding a copy of as many Scalars from `data` as the shape holds.
template <typename Scalar>
pybind11::array_t<Scalar> to_numpy(const Scalar* data, std::vector<pybind11::ssize_t> shape) {
    pybind11::array_t<Scalar> result(shape);
    if (result.size() > 0) std::memcpy(result.mutable_data(), data, static_cast<size_t>(result.size()) * sizeof(Scalar));
    return result;
}

// The data of `out`, an array the caller keeps and C++ writes into, after checking that it is exactly
// what the writes need: Scalar, C-contiguous, writeable, of `shape` (no conversion, which would write
// into a copy the caller never sees). Throws hairlod::Error naming `name` and the shape expected.
template <typename Scalar>
Scalar* output_data(pybind11::array& out, const std::vector<pybind11::ssize_t>& shape, const char* name) {
    bool fits = out.dtype().is(pybind11::dtype::of<Scalar>()) && (out.flags() & pybind11::array::c_style) && out.writeable() &&
                out.ndim() == static_cast<pybind11::ssize_t>(shape.size());
    for (size_t i = 0; fits && i < shape.size(); ++i) fits = out.shape(static_cast<pybind11::ssize_t>(i)) == shape[i];
    if (!fits) {
        std::string expected;
        for (pybind11::ssize_t extent : shape) expected += (expected.empty() ? "" : ", ") + std::to_string(extent);
        throw Error(std::string(name) + " must be a writeable, C-contiguous " +
                    pybind11::str(pybind11::dtype::of<Scalar>()).cast<std::string>() + " array of shape [" + expected + "]");
    }
    return static_cast<Scalar*>(out.mutable_data());
}

// A numpy array with `shape` over the data of `values`, which it takes over (no copy: for arrays of
// tens of MB made once, where the copy costs as much as computing them). Throws hairlod::Error when
// the shape does not hold exactly that many Scalars.
template <typename Scalar, typename T>
pybind11::array_t<Scalar> moved_to_numpy(std::vector<T>&& values, std::vector<pybind11::ssize_t> shape) {
    pybind11::ssize_t size = 1;
    for (pybind11::ssize_t extent : shape) size *= extent;
    if (static_cast<size_t>(size) * sizeof(Scalar) != values.size() * sizeof(T))
        throw Error("moved_to_numpy: the shape does not match the data");
    auto* owner = new std::vector<T>(std::move(values));
    const pybind11::capsule release(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return pybind11::array_t<Scalar>(shape, reinterpret_cast<const Scalar*>(owner->data()), release);
}

}  // namespace hairlod::python
