// geotex._geotex: the compiled part of the Python module (the package geotex wraps it with real
// signatures made from the option tables; see geotex/__init__.py).

#include "common.h"

#include "geotex/core/error.h"
#include "geotex/core/progress.h"

PYBIND11_MODULE(_geotex, m) {
  m.doc() = "geotex: 3D shape modeling with high-level descriptors (compiled core)";
  // Typed errors: InvalidInput is a ValueError, IoError an OSError, SolverError a RuntimeError,
  // running out of memory (OutOfMemory, std::bad_alloc) a MemoryError.
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
    } catch (const geotex::OutOfMemory& e) {  // an estimate made before the work: a MemoryError with its figures
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const geotex::Interrupted&) {  // run() turns it into the SIGINT's KeyboardInterrupt; this is a fallback
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const geotex::Error& e) {
      error(e.what());
    }
  });
  geotex::python::bind_core(m);
  geotex::python::bind_toolkit(m);
  geotex::python::bind_denoise(m);
  geotex::python::bind_texture(m);
  geotex::python::bind_synthesis(m);
  geotex::python::bind_resize(m);
  geotex::python::bind_tools(m);
}
