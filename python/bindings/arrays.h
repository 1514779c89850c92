// Between numpy and cmbrl's vectors in the Python module: arrays that own C++ vectors (no copy
// back), real-valued input checked by shape and dtype with errors that name it, and boxes.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/env/env.h"

namespace cmbrl::python {

namespace py = pybind11;

using Doubles = py::array_t<double, py::array::c_style>;

// A numpy array that takes `values` over without copying them, shaped `shape`: the capsule owns
// the vector from here on and frees it with the array.
template <typename T>
py::array_t<T> Own(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto owned = std::make_unique<std::vector<T>>(std::move(values));
  T* data = owned->data();
  py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  owned.release();  // the capsule owns it now
  return py::array_t<T>(shape, data, owner);
}

inline py::array_t<double> Own(std::vector<double>&& values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  return Own<double>(std::move(values), {n});
}

// Any real-valued array-like of exactly `shape` (float or integer dtype) as doubles, row-major;
// `what` names it in the error otherwise.
inline std::vector<double> RealValues(const py::handle& values,
                                      const std::vector<py::ssize_t>& shape, const char* what) {
  const py::array array = py::array::ensure(values);
  Require(static_cast<bool>(array), "{}: expected a numpy array or a sequence of numbers", what);
  // Messages are built only on failure: this runs once per environment step.
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    Fail("{} has dtype {}: expected real numbers (float or integer)", what,
         std::string(py::str(array.dtype())));
  }
  std::vector<py::ssize_t> got(array.shape(), array.shape() + array.ndim());
  if (got != shape) {
    Fail("{} has shape {}: expected {}", what, std::string(py::str(py::tuple(py::cast(got)))),
         std::string(py::str(py::tuple(py::cast(shape)))));
  }
  const Doubles converted = Doubles::ensure(array);
  return std::vector<double>(converted.data(), converted.data() + converted.size());
}

// A Python exception as "TypeName: message", without the traceback that what() carries.
inline std::string PythonErrorText(const py::error_already_set& error) {
  const std::string type = py::str(error.type().attr("__name__"));
  const std::string message = py::str(error.value());
  return message.empty() ? type : type + ": " + message;
}

// The number of rows of a 2-D array; `what` names it in the error otherwise.
inline py::ssize_t RowsOf(const py::handle& array, const char* what) {
  const py::array a = py::array::ensure(array);
  Require(static_cast<bool>(a) && a.ndim() == 2, "{}: expected a 2-D array (rows, columns)", what);
  return a.shape(0);
}

// Rows of a 2-D real array of `width` columns, as doubles.
inline std::vector<double> Matrix(const py::handle& array, py::ssize_t rows, py::ssize_t width,
                                  const char* what) {
  return RealValues(array, {rows, width}, what);
}

// (N) 0/1 bytes as a bool array.
inline py::array_t<bool> Flags(const std::vector<std::uint8_t>& values) {
  py::array_t<bool> out(static_cast<py::ssize_t>(values.size()));
  bool* data = out.mutable_data();
  for (size_t k = 0; k < values.size(); ++k) data[k] = values[k] != 0;
  return out;
}

// A box's bounds and component names.
inline py::dict BoxDict(const BoxSpec& box) {
  py::dict d;
  d["low"] = Own(std::vector<double>(box.low));
  d["high"] = Own(std::vector<double>(box.high));
  d["names"] = box.names;
  return d;
}

}  // namespace cmbrl::python
