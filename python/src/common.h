#pragma once
// Shared pieces of the Python bindings: strict numpy <-> mesh conversion, options from keyword
// dictionaries through the option tables (geotex/core/options.h), running without the GIL, progress.
//
// Every binding takes its options as one dict (the Python wrappers in geotex/__init__.py build it
// from real keyword arguments whose names and defaults come from the same tables) and converts
// its inputs while holding the GIL; only the computation runs without it.

#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <type_traits>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"
#include "geotex/core/results.h"

namespace py = pybind11;

namespace geotex::python {

using VArray = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using FArray = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

// ---------------------------------------------------------------------------------------------
// Arrays

//! #N by 3 finite float positions from any array-like of real numbers (integers allowed).
//! \throw InvalidInput for another shape, a non-numeric dtype, NaN or infinity.
MatrixX3d to_points(py::handle a, const char* what);
//! #N by 3 vertex indices from an integer array-like: every index in [0, n_vertices). Floats, bools
//! and indices that do not fit are refused (no silent narrowing). \throw InvalidInput.
MatrixX3i to_faces(py::handle a, Eigen::Index n_vertices, const char* what);
//! #N by \p columns integers in [0, n) (\p columns 0: a one-dimensional array, #N by 1), from an integer
//! array-like; out-of-range values are named exactly ("row 0 has vertex index 18446744073709551615 out of
//! range [0, 12)"), never wrapped or rounded. \throw InvalidInput.
Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic> to_indices(py::handle a, Eigen::Index n, int columns,
                                                               const char* what, const char* index_name);
//! A vector of #n finite reals. \throw InvalidInput.
Eigen::VectorXd to_vector(py::handle a, Eigen::Index n, const char* what);
//! A mesh from positions and faces (both checked as above); faces dropped by make_mesh() raise a
//! UserWarning (with the GIL held). \throw InvalidInput for no faces.
//! A UserWarning; needs the GIL (never call it inside run()'s released section).
void warn(const std::string& message);
Mesh to_mesh(py::handle V, py::handle F);
//! (V, F) of a mesh as numpy arrays (V float64 #V×3, F int32 #F×3).
py::tuple from_mesh(const Mesh& mesh);

// ---------------------------------------------------------------------------------------------
// Options

//! A Python value for an option value (None for "auto", tuples for Vec3).
py::object to_python(const OptionValue& v);
//! The option value of \p obj for option \p info: bool for Bool, int for Int (not float or bool),
//! int or float for Real (finite), str for Text/Choice, three numbers for Vec3, None for "auto".
//! \throw InvalidOption (a ValueError) or py::type_error naming the option.
OptionValue from_python(const OptionInfo& info, py::handle obj);

//! What every call takes besides its options: a preset name, a progress callback, a thread count.
struct CallOptions {
  std::string preset;
  ProgressFn progress;        // calls the Python callback with the GIL; raises KeyboardInterrupt on Ctrl-C
  std::optional<int> threads;
};
//! Split \p kw into the call options ("preset", "progress", "threads") and the rest.
CallOptions call_options(py::dict& kw);

//! An options struct from a dict of option names (Python spelling: a trailing '_' is dropped, for
//! `lambda_`): the defaults (or \p start), then the preset, then the given values, checked.
template <class O>
O to_options(py::dict kw, const CallOptions& call, O start = O{}, const OptionTable<O>& table = O::table()) {
  if (!call.preset.empty()) table.apply_preset(start, call.preset);
  for (auto item : kw) {
    std::string name = py::cast<std::string>(item.first);
    if (!name.empty() && name.back() == '_') name.pop_back();
    const auto* f = table.find(name);
    if (!f) throw py::type_error("unexpected keyword argument '" + name + "'");
    f->set(start, from_python(f->info, item.second));
  }
  table.check(start);
  return start;
}

//! The options of \p o as a dict of Python values (the parameters a run used).
template <class O>
py::dict options_dict(const O& o, const OptionTable<O>& table = O::table()) {
  py::dict d;
  for (const auto& [name, v] : table.values(o)) d[py::str(name)] = to_python(v);
  return d;
}

//! The description of a table for the Python side: {"fields": [{name, kind, default, help, ref, lo,
//! hi, lo_open, hi_open, choices, automatic}], "presets": {name: help}}.
template <class O>
py::dict table_description(const OptionTable<O>& table = O::table()) {
  py::list fields;
  const O defaults{};
  for (const auto& f : table.fields()) {
    py::dict d;
    d["name"] = f.info.name;
    static const char* kinds[] = {"bool", "int", "float", "str", "choice", "vec3"};
    d["kind"] = kinds[static_cast<int>(f.info.kind)];
    d["default"] = to_python(f.get(defaults));
    d["help"] = f.info.help;
    d["ref"] = f.info.ref;
    d["lo"] = f.info.bounds.lo;
    d["hi"] = f.info.bounds.hi;
    d["lo_open"] = f.info.bounds.lo_open;
    d["hi_open"] = f.info.bounds.hi_open;
    d["choices"] = f.info.choices;
    d["automatic"] = f.info.automatic;
    fields.append(d);
  }
  py::dict presets;
  for (const auto& p : table.presets()) presets[py::str(p.name)] = p.help;
  py::dict out;
  out["fields"] = fields;
  out["presets"] = presets;
  return out;
}

//! The tables the Python side sees, by struct name (filled by each bind_* file).
std::map<std::string, std::function<py::dict()>>& option_tables();
//! Checks of a dict of options against each table, as a call would make them (no computation): for
//! batch runs, which validate every option before any file is processed.
std::map<std::string, std::function<void(py::dict)>>& option_checkers();
template <class O>
void register_table(const std::string& name) {
  option_tables()[name] = [] { return table_description<O>(); };
  option_checkers()[name] = [](py::dict kw) {
    py::dict copy(kw);
    const CallOptions call = call_options(copy);
    (void)to_options<O>(copy, call);
  };
}

// ---------------------------------------------------------------------------------------------
// Results (geotex/core/results.h): the fields of a result table, the same the CLI's --report writes

//! A JSON value as Python objects (objects as dicts, arrays as lists).
py::object from_json(const nlohmann::json& j);

//! An Array or IntArray field as a numpy array: a vector for one column, else rows.
py::object result_array(const Eigen::MatrixXd& a, bool integers);

//! Every field of \p table for \p r into \p d: Array fields as numpy arrays, the others from their JSON.
template <class R>
void put_results(py::dict& d, const R& r, const ResultTable<R>& table) {
  for (const auto& f : table.fields()) {
    if (f.info.kind == ResultKind::Array || f.info.kind == ResultKind::IntArray) {
      d[py::str(f.info.name)] = result_array(f.array(r), f.info.kind == ResultKind::IntArray);
    } else {
      d[py::str(f.info.name)] = from_json(f.json(r));
    }
  }
}

//! The result tables the Python side sees (for its typed result classes and stubs), by name:
//! [{name, kind, help, unit, in_report, optional}].
std::map<std::string, std::function<py::list()>>& result_tables();
template <class R>
void register_results(const std::string& name, const ResultTable<R>& (*table)()) {
  result_tables()[name] = [table] {
    static const char* kinds[] = {"bool", "int", "float", "str", "texts", "reals", "ints", "array", "record",
                                  "int_array"};
    py::list fields;
    for (const auto& f : table().fields()) {
      py::dict d;
      d["name"] = f.info.name;
      d["kind"] = kinds[static_cast<int>(f.info.kind)];
      d["help"] = f.info.help;
      d["unit"] = f.info.unit;
      d["in_report"] = f.info.in_report;
      d["optional"] = f.info.optional;
      fields.append(d);
    }
    return fields;
  };
}

// ---------------------------------------------------------------------------------------------
// Running

//! The OpenMP thread count for one call (restored afterwards).
class ThreadScope {
 public:
  explicit ThreadScope(std::optional<int> threads);
  ~ThreadScope();

 private:
  int previous_ = 0;
  int previous_blas_ = 0;
  bool set_ = false;
};

//! Raise a signal that arrived during a call (KeyboardInterrupt for Ctrl-C) once the GIL is held again:
//! a SIGINT raised at or after the last progress report, or in a call that reports none, is not lost.
void raise_pending_signals();

//! Ctrl-C during a call from the main thread (issue 30): while alive, a SIGINT still reaches Python's own
//! handler and also sets a flag that the library's cancellation points (check_interrupt()) read, so the
//! computation stops within a few milliseconds instead of at its next progress report or its end. Only
//! while SIGINT is Python's default_int_handler (which raises KeyboardInterrupt); other threads and other
//! handlers keep the old behaviour (the signal is raised once the call returns). Construct with the GIL.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  //! The flag to watch, or null when this call cannot be interrupted early.
  const std::atomic<bool>* flag() const { return active_ ? &flag_ : nullptr; }
  //! What the signal handler does (async-signal-safe).
  static void set_flag() noexcept;

 private:
  bool active_ = false;
  static std::atomic<bool> flag_;
};

//! Without the GIL: f() inside the guard's InterruptScope, if any.
template <class F>
auto interruptible(const InterruptGuard& guard, F&& f) -> decltype(f()) {
  if (!guard.flag()) return f();
  InterruptScope scope(*guard.flag());
  return f();
}

//! After an Interrupted (GIL held): the KeyboardInterrupt of the SIGINT that caused it.
[[noreturn]] void raise_interrupt();

//! Run \p f without the GIL and with the requested thread count; exceptions propagate, and a signal that
//! arrived during the call is raised before any result is returned.
template <class F>
auto run(const CallOptions& call, F&& f) -> decltype(f()) {
  // A Ctrl-C during the conversions before this (the GIL held, Python's handler only recorded it):
  // KeyboardInterrupt now, not after the whole computation.
  raise_pending_signals();
  ThreadScope threads(call.threads);
  InterruptGuard guard;
  try {
    if constexpr (std::is_void_v<decltype(f())>) {
      {
        py::gil_scoped_release release;
        interruptible(guard, f);
      }
      raise_pending_signals();
    } else {
      auto result = [&] {
        py::gil_scoped_release release;
        return interruptible(guard, f);
      }();
      raise_pending_signals();
      return result;
    }
  } catch (const Interrupted&) {
    raise_interrupt();
  }
}

//! f() timed (wall seconds into \p seconds), as the CLI times the library call it reports; call it inside
//! run() so that only the computation is timed.
template <class F>
auto timed(double& seconds, F&& f) -> decltype(f()) {
  const auto t0 = std::chrono::steady_clock::now();
  auto result = f();
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

// One bind_* per topic.
void bind_core(py::module_& m);     // files, shapes, noise, geometry, metrics, option tables
void bind_toolkit(py::module_& m);  // ch. 5: Laplacians, smoothing, editing, Phong projection, 1-forms, parametrization, ADF
void bind_denoise(py::module_& m);  // ch. 6-7
void bind_texture(py::module_& m);  // ch. 8
void bind_synthesis(py::module_& m);  // texture synthesis (issue 20)
void bind_resize(py::module_& m);   // ch. 9
void bind_tools(py::module_& m);    // render, view

}  // namespace geotex::python
