// geotex._geotex: the compiled part of the Python module.

#include "common.h"

#include <fmt/format.h>

#include "geotex/core/error.h"

namespace geotex::python {

Mesh to_mesh(const Eigen::Ref<const MatrixX3d>& V, const Eigen::Ref<const MatrixX3i>& F) {
  BuildReport rep;
  Mesh mesh = make_mesh(V, F, &rep);
  if (rep.dropped() > 0) {
    const std::string msg = fmt::format(
        "geotex dropped {} face(s) to build a manifold mesh ({} degenerate, {} duplicate, {} non-manifold)",
        rep.dropped(), rep.degenerate_faces, rep.duplicate_faces, rep.nonmanifold_faces);
    if (PyErr_WarnEx(PyExc_UserWarning, msg.c_str(), 1) != 0) throw py::error_already_set();
  }
  if (mesh.n_faces() == 0) throw InvalidInput("the mesh has no faces");
  return mesh;
}

py::tuple from_mesh(const Mesh& mesh) {
  VArray V = positions(mesh);
  FArray F = faces(mesh);
  return py::make_tuple(V, F);
}

}  // namespace geotex::python

PYBIND11_MODULE(_geotex, m) {
  m.doc() = "geotex: 3D shape modeling with high-level descriptors (compiled core)";
  // Typed errors: InvalidInput is a ValueError, IoError an OSError, SolverError a RuntimeError.
  static py::exception<geotex::Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<geotex::InvalidInput> invalid(m, "InvalidInput", PyExc_ValueError);
  static py::exception<geotex::IoError> io(m, "IoError", PyExc_OSError);
  static py::exception<geotex::SolverError> solver(m, "SolverError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const geotex::InvalidInput& e) {
      invalid(e.what());
    } catch (const geotex::IoError& e) {
      io(e.what());
    } catch (const geotex::SolverError& e) {
      solver(e.what());
    } catch (const geotex::Error& e) {
      error(e.what());
    }
  });
  geotex::python::bind_core(m);
  geotex::python::bind_extras(m);
}
