#pragma once
// Shared helpers of the Python bindings: numpy (V, F) <-> geotex::Mesh, option parsing.

#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "geotex/core/mesh.h"

namespace py = pybind11;

namespace geotex::python {

using VArray = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using FArray = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

//! Build a mesh from numpy arrays; warns (Python warning) when faces had to be dropped.
Mesh to_mesh(const Eigen::Ref<const MatrixX3d>& V, const Eigen::Ref<const MatrixX3i>& F);
//! (V, F) tuple of a mesh as numpy arrays (V float64 #V×3, F int32 #F×3).
py::tuple from_mesh(const Mesh& mesh);

// One bind_* per topic file.
void bind_core(py::module_& m);
void bind_extras(py::module_& m);  // capabilities beyond the foundation (denoise, texture, …)

}  // namespace geotex::python
