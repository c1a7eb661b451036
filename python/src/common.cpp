#include "common.h"

#include "geotex/core/resources.h"

#include <csignal>
#include <cmath>
#include <limits>

#include <signal.h>

#include <fmt/format.h>
#include <omp.h>

#include "geotex/core/error.h"

namespace geotex::python {

namespace {

// The array as a numpy array of its own dtype (no conversion yet), two-dimensional N × 3.
py::array as_array(py::handle a, const char* what) {
  py::array arr;
  try {
    arr = py::array::ensure(a);
  } catch (const py::error_already_set&) {
  }
  if (!arr) throw InvalidInput(fmt::format("{}: expected an array of numbers", what));
  return arr;
}

void check_n_by_3(const py::array& arr, const char* what) {
  if (arr.ndim() != 2 || arr.shape(1) != 3)
    throw InvalidInput(fmt::format("{}: expected an N x 3 array, got shape ({})", what, [&] {
      std::string s;
      for (py::ssize_t k = 0; k < arr.ndim(); ++k) s += (k ? ", " : "") + std::to_string(arr.shape(k));
      return s;
    }()));
}

}  // namespace

MatrixX3d to_points(py::handle a, const char* what) {
  const py::array arr = as_array(a, what);
  check_n_by_3(arr, what);
  const char kind = arr.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw InvalidInput(fmt::format("{}: expected real numbers, got dtype {}", what, std::string(py::str(arr.dtype()))));
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  MatrixX3d X(d.shape(0), 3);
  const double* p = d.data();
  for (py::ssize_t i = 0; i < d.shape(0); ++i)
    for (int k = 0; k < 3; ++k) {
      const double v = p[3 * i + k];
      if (!std::isfinite(v))
        throw InvalidInput(fmt::format("{}: row {} has a non-finite coordinate ({})", what, i, v));
      X(i, k) = v;
    }
  return X;
}

Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic> to_indices(py::handle a, Eigen::Index n, int columns,
                                                               const char* what, const char* index_name) {
  const py::array arr = as_array(a, what);
  if (columns == 3) {
    check_n_by_3(arr, what);
  } else if (columns > 0 ? arr.ndim() != 2 || arr.shape(1) != columns : arr.ndim() != 1) {
    throw InvalidInput(columns > 0 ? fmt::format("{}: expected an N x {} array of integers", what, columns)
                                   : fmt::format("{}: expected a one-dimensional array of integers", what));
  }
  const char kind = arr.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw InvalidInput(fmt::format("{}: {} values must be integers, got dtype {}", what, index_name,
                                   std::string(py::str(arr.dtype()))));
  const py::ssize_t rows = arr.ndim() > 0 ? arr.shape(0) : 0, cols = columns > 0 ? columns : 1;
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic> out(rows, cols);
  // Read as int64 (or uint64) first, so that an index that does not fit an int is seen, not wrapped, and
  // printed as the integer it is (2^64 - 1 stays 18446744073709551615): no floating point on the way.
  auto out_of_range = [&](py::ssize_t i, const std::string& v) {
    throw InvalidInput(fmt::format("{}: row {} has {} {} out of range [0, {})", what, i, index_name, v, n));
  };
  if (kind == 'u') {
    const auto d = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
    for (py::ssize_t i = 0; i < rows; ++i)
      for (py::ssize_t k = 0; k < cols; ++k) {
        const uint64_t v = d.data()[cols * i + k];
        if (v >= static_cast<uint64_t>(n)) out_of_range(i, std::to_string(v));
        out(i, k) = static_cast<int>(v);
      }
  } else {
    const auto d = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
    for (py::ssize_t i = 0; i < rows; ++i)
      for (py::ssize_t k = 0; k < cols; ++k) {
        const int64_t v = d.data()[cols * i + k];
        if (v < 0 || v >= static_cast<int64_t>(n)) out_of_range(i, std::to_string(v));
        out(i, k) = static_cast<int>(v);
      }
  }
  return out;
}

MatrixX3i to_faces(py::handle a, Eigen::Index n_vertices, const char* what) {
  return to_indices(a, n_vertices, 3, what, "vertex index");
}

Eigen::VectorXd to_vector(py::handle a, Eigen::Index n, const char* what) {
  const py::array arr = as_array(a, what);
  const char kind = arr.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw InvalidInput(fmt::format("{}: expected real numbers, got dtype {}", what, std::string(py::str(arr.dtype()))));
  if (arr.ndim() != 1 || (n >= 0 && arr.shape(0) != n))
    throw InvalidInput(fmt::format("{}: expected {} values in a one-dimensional array", what,
                                   n >= 0 ? std::to_string(n) : std::string("N")));
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  Eigen::VectorXd v(d.shape(0));
  for (py::ssize_t i = 0; i < d.shape(0); ++i) {
    if (!std::isfinite(d.data()[i])) throw InvalidInput(fmt::format("{}: value {} is not finite", what, i));
    v[i] = d.data()[i];
  }
  return v;
}

void warn(const std::string& message) {
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
}

Mesh to_mesh(py::handle V, py::handle F) {
  const MatrixX3d X = to_points(V, "V");
  const MatrixX3i T = to_faces(F, X.rows(), "F");
  BuildReport rep;
  Mesh mesh = make_mesh(X, T, &rep);
  if (rep.dropped() > 0) {  // a warning needs the GIL: conversions happen before any release
    const std::string msg = fmt::format(
        "geotex dropped {} face(s) to build a manifold mesh ({} degenerate, {} duplicate, {} non-manifold)",
        rep.dropped(), rep.degenerate_faces, rep.duplicate_faces, rep.nonmanifold_faces);
    warn(msg);
  }
  if (mesh.n_faces() == 0) throw InvalidInput("the mesh has no faces");
  return mesh;
}

py::tuple from_mesh(const Mesh& mesh) {
  VArray V = positions(mesh);
  FArray F = faces(mesh);
  return py::make_tuple(V, F);
}

py::object to_python(const OptionValue& v) {
  struct {
    py::object operator()(std::monostate) const { return py::none(); }
    py::object operator()(bool b) const { return py::bool_(b); }
    py::object operator()(int64_t i) const { return py::int_(i); }
    py::object operator()(double d) const { return py::float_(d); }
    py::object operator()(const std::string& s) const { return py::str(s); }
    py::object operator()(const Vec3& p) const { return py::make_tuple(p[0], p[1], p[2]); }
  } f;
  return std::visit(f, v);
}

OptionValue from_python(const OptionInfo& info, py::handle obj) {
  const auto type_error = [&](const char* expected) {
    return py::type_error(fmt::format("{}: expected {}, got {}", info.name, expected,
                                      std::string(py::str(py::type::of(obj).attr("__name__")))));
  };
  if (obj.is_none()) {
    if (info.automatic) return std::monostate{};
    throw type_error(info.kind == OptionKind::Bool ? "True or False" : "a value (None means 'auto' only for automatic options)");
  }
  // numpy scalars are accepted through their Python equivalents; bools are not numbers here.
  const bool is_bool = py::isinstance<py::bool_>(obj) || py::str(py::type::of(obj).attr("__name__")).cast<std::string>() == "bool_";
  const auto is_int = [&] {
    return !is_bool && (py::isinstance<py::int_>(obj) || py::hasattr(obj, "__index__"));
  };
  const auto is_real = [&] { return !is_bool && (is_int() || py::isinstance<py::float_>(obj) || py::hasattr(obj, "__float__")); };
  OptionValue v;
  switch (info.kind) {
    case OptionKind::Bool:
      if (!is_bool) throw type_error("True or False");
      v = obj.cast<bool>();
      break;
    case OptionKind::Int: {
      if (!is_int()) throw type_error("an integer");
      const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(obj.ptr()));
      if (!i) throw py::error_already_set();
      const double d = py::cast<double>(py::float_(i));
      if (std::abs(d) > 9.0e15) throw InvalidOption(fmt::format("option {}: {} is out of range", info.name, py::str(static_cast<py::handle>(i)).cast<std::string>()));
      v = static_cast<int64_t>(py::cast<long long>(i));
      break;
    }
    case OptionKind::Real:
      if (!is_real()) throw type_error("a number");
      v = py::cast<double>(py::float_(py::reinterpret_borrow<py::object>(obj)));
      break;
    case OptionKind::Text:
    case OptionKind::Choice:
      if (!py::isinstance<py::str>(obj)) throw type_error("a string");
      v = obj.cast<std::string>();
      break;
    case OptionKind::Vec3: {
      if (py::isinstance<py::str>(obj) || !py::isinstance<py::sequence>(py::reinterpret_borrow<py::object>(obj)) &&
                                              !py::hasattr(obj, "__array__"))
        throw type_error("three numbers");
      const py::array a = py::array::ensure(obj);
      if (!a || a.ndim() != 1 || a.shape(0) != 3 || (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u'))
        throw type_error("three numbers");
      const auto d = py::array_t<double, py::array::forcecast>::ensure(a);
      v = Vec3(d.at(0), d.at(1), d.at(2));
      break;
    }
  }
  check_option_value(info, v);
  return v;
}

CallOptions call_options(py::dict& kw) {
  CallOptions c;
  if (kw.contains("preset")) {
    py::object p = kw["preset"];
    if (!p.is_none()) {
      if (!py::isinstance<py::str>(p)) throw py::type_error("preset: expected a string");
      c.preset = p.cast<std::string>();
    }
    PyDict_DelItemString(kw.ptr(), "preset");
  }
  if (kw.contains("threads")) {
    py::object t = kw["threads"];
    if (!t.is_none()) {
      if (py::isinstance<py::bool_>(t) || !py::isinstance<py::int_>(t)) throw py::type_error("threads: expected an integer");
      const long long n = t.cast<long long>();
      if (n < 1 || n > 4096) throw InvalidOption(fmt::format("option threads: {} is out of range (in [1, 4096])", n));
      c.threads = static_cast<int>(n);
    }
    PyDict_DelItemString(kw.ptr(), "threads");
  }
  if (kw.contains("progress")) {
    py::object cb = kw["progress"];
    PyDict_DelItemString(kw.ptr(), "progress");
    if (!cb.is_none()) {
      if (!PyCallable_Check(cb.ptr())) throw py::type_error("progress: expected a callable(fraction, stage)");
      // Called from the computation (without the GIL): take the GIL, call, and let a pending Ctrl-C or
      // an exception of the callback end the computation (it propagates as a C++ exception).
      auto holder = std::make_shared<py::object>(cb);
      c.progress = [holder](double fraction, std::string_view stage) {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        (*holder)(fraction, std::string(stage));
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // a signal the callback raised
      };
    }
  } else {
    // Without a callback, Ctrl-C still stops a long computation at its next progress report.
    c.progress = [](double, std::string_view) {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    };
  }
  return c;
}

namespace {

// Python's own SIGINT action, called first by ours (it records the signal and wakes the interpreter).
struct sigaction g_python_sigint {};
int g_guard_depth = 0;  // guards alive in the main thread (nested calls from progress callbacks); GIL held

extern "C" void geotex_python_sigint(int sig, siginfo_t* info, void* context) {
  InterruptGuard::set_flag();
  if (g_python_sigint.sa_flags & SA_SIGINFO) {
    g_python_sigint.sa_sigaction(sig, info, context);
  } else if (g_python_sigint.sa_handler != SIG_DFL && g_python_sigint.sa_handler != SIG_IGN) {
    g_python_sigint.sa_handler(sig);
  }
}

// Whether a Ctrl-C now would raise KeyboardInterrupt in this thread: the main thread, with SIGINT
// handled by signal.default_int_handler.
bool default_interrupt_in_main_thread() {
  const py::module_ threading = py::module_::import("threading");
  if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return false;
  const py::module_ signal = py::module_::import("signal");
  return signal.attr("getsignal")(signal.attr("SIGINT")).is(signal.attr("default_int_handler"));
}

}  // namespace

std::atomic<bool> InterruptGuard::flag_{false};

void InterruptGuard::set_flag() noexcept { flag_.store(true, std::memory_order_relaxed); }

InterruptGuard::InterruptGuard() {
  if (!default_interrupt_in_main_thread()) return;
  if (g_guard_depth == 0) {
    struct sigaction current {};
    if (::sigaction(SIGINT, nullptr, &current) != 0) return;
    struct sigaction ours {};
    ours.sa_sigaction = geotex_python_sigint;
    ours.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESTART;
    sigemptyset(&ours.sa_mask);
    g_python_sigint = current;
    flag_.store(false, std::memory_order_relaxed);  // a SIGINT before this call was raised by Python already
    if (::sigaction(SIGINT, &ours, nullptr) != 0) return;
  }
  ++g_guard_depth;
  active_ = true;
}

InterruptGuard::~InterruptGuard() {
  if (!active_ || --g_guard_depth > 0) return;
  // Put Python's action back, unless the program replaced ours meanwhile (signal.signal in a callback).
  struct sigaction current {};
  if (::sigaction(SIGINT, nullptr, &current) == 0 && (current.sa_flags & SA_SIGINFO) &&
      current.sa_sigaction == geotex_python_sigint)
    ::sigaction(SIGINT, &g_python_sigint, nullptr);
}

void raise_interrupt() {
  raise_pending_signals();  // Python's handler saw the SIGINT: KeyboardInterrupt
  PyErr_SetNone(PyExc_KeyboardInterrupt);
  throw py::error_already_set();
}

void raise_pending_signals() {
  // Handlers run only in the main thread; elsewhere this is a no-op and the signal waits for it.
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

ThreadScope::ThreadScope(std::optional<int> threads) {
  // One BLAS thread during the call (OpenBLAS's spinning workers, resources.h); numpy's count after it.
  previous_blas_ = set_blas_threads(1);
  if (!threads) return;
  previous_ = omp_get_max_threads();
  omp_set_num_threads(*threads);
  set_ = true;
}

ThreadScope::~ThreadScope() {
  if (previous_blas_ > 0) set_blas_threads(previous_blas_);
  if (set_) omp_set_num_threads(previous_);
}

py::object from_json(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& x : j) l.append(from_json(x));
      return std::move(l);
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = from_json(v);
      return std::move(d);
    }
    default: throw py::type_error("a result value of an unexpected JSON type");
  }
}

py::object result_array(const Eigen::MatrixXd& a, bool integers) {
  using RowsD = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using RowsI = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  if (a.cols() == 1) {
    if (integers) return py::cast(Eigen::VectorXi(a.col(0).cast<int>()));
    return py::cast(Eigen::VectorXd(a.col(0)));
  }
  if (integers) return py::cast(RowsI(a.cast<int>()));
  return py::cast(RowsD(a));
}

std::map<std::string, std::function<py::list()>>& result_tables() {
  static std::map<std::string, std::function<py::list()>> t;
  return t;
}

std::map<std::string, std::function<py::dict()>>& option_tables() {
  static std::map<std::string, std::function<py::dict()>> t;
  return t;
}

std::map<std::string, std::function<void(py::dict)>>& option_checkers() {
  static std::map<std::string, std::function<void(py::dict)>> t;
  return t;
}

}  // namespace geotex::python
