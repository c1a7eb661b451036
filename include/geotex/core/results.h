#pragma once
//! \file results.h One description per result struct, as options.h gives one per options struct (issue 29).
//!
//! A ResultTable lists the fields a front end shows of a result: name, kind, one-line help, unit. From it
//!  - the CLI writes its `--report` JSON (report(): every field marked for the report),
//!  - the Python module fills its result objects (every field; arrays as numpy arrays),
//!  - the Python stubs declare typed result classes (geotex._stubgen).
//! So a report key and a Python attribute are one name for one thing, declared once. The tables live
//! beside the functions that return the results (e.g. denoise/results.h).
//!
//!   const ResultTable<MrfResult>& mrf_results() {
//!     static const auto t = ResultTable<MrfResult>()
//!         .add("iterations", [](const MrfResult& r) { return r.iterations; }, "outer iterations run")
//!         .add("vertex_energy", …, "U_V after each outer iteration", "", /*in_report=*/false);
//!     return t;
//!   }

#include <algorithm>
#include <functional>
#include <initializer_list>
#include <stdexcept>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace geotex {

//! How a field is shown: Python's type of it (Array: a numpy array of doubles, IntArray: of integers;
//! Record: a dict of named values).
enum class ResultKind { Bool, Int, Real, Text, Texts, Reals, Ints, Array, Record, IntArray };

//! The description of one result field.
struct ResultFieldInfo {
  std::string name;        //!< the report key and the Python attribute
  ResultKind kind = ResultKind::Real;
  std::string help;        //!< one line
  std::string unit;        //!< e.g. "s", "deg", "mean edge lengths"; empty when dimensionless or obvious
  bool in_report = true;   //!< false: Python only (per-vertex arrays the CLI writes as files, old spellings)
  bool optional = false;   //!< may be absent: null in JSON, None in Python (e.g. a volume of an open mesh)
};

//! The in_report argument of a field the CLI report leaves out (ResultTable::add, ::array).
inline constexpr bool kPythonOnly = false;

//! One field as a caption or a summary line says it: its name read aloud (underscores as spaces, a trailing
//! unit dropped: `mean_normal_error_deg` -> "mean normal error"), its value (reals to 3 significant digits)
//! and its unit: "mean normal error 2.81 deg". Arrays and records are not said (std::logic_error).
std::string figure_text(const ResultFieldInfo& field, const nlohmann::json& value);

//! A #rows by #cols numeric array as JSON: a flat list for one column, else a list of rows.
nlohmann::json array_json(const Eigen::MatrixXd& a);

template <class R>
class ResultTable {
 public:
  struct Field {
    ResultFieldInfo info;
    std::function<nlohmann::json(const R&)> json;   //!< the value (for an Array: array_json of array())
    std::function<Eigen::MatrixXd(const R&)> array;  //!< Array fields only: the values as a matrix
  };
  //! A field of a plain type, its kind from the getter's return type: bool, an integer, double,
  //! std::string, std::vector of double, int or std::string; or nlohmann::json (a Record); or a
  //! std::optional of one of these (an optional field).
  template <class G>
  ResultTable& add(std::string name, G get, std::string help, std::string unit = {}, bool in_report = true) {
    using T = std::decay_t<std::invoke_result_t<G, const R&>>;
    Field f;
    if constexpr (is_optional<T>::value) {
      f.info = {std::move(name), kind_of<typename T::value_type>(), std::move(help), std::move(unit), in_report, true};
      f.json = [get](const R& r) {
        const T v = get(r);
        return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
      };
    } else {
      f.info = {std::move(name), kind_of<T>(), std::move(help), std::move(unit), in_report};
      f.json = [get](const R& r) { return nlohmann::json(get(r)); };
    }
    fields_.push_back(std::move(f));
    return *this;
  }
  //! A numeric array field (a vector or a matrix; held as doubles, shown as integers when it is of integers).
  template <class G>
  ResultTable& array(std::string name, G get, std::string help, std::string unit = {}, bool in_report = true) {
    using T = typename std::decay_t<std::invoke_result_t<G, const R&>>::Scalar;
    Field f;
    f.info = {std::move(name), std::is_integral_v<T> ? ResultKind::IntArray : ResultKind::Array, std::move(help),
              std::move(unit), in_report};
    f.array = [get](const R& r) -> Eigen::MatrixXd { return get(r).template cast<double>(); };
    f.json = [a = f.array](const R& r) { return array_json(a(r)); };
    fields_.push_back(std::move(f));
    return *this;
  }

  //! The fields of \p table, read from the part of a result that \p get returns (e.g. a summary it holds).
  template <class S, class G>
  ResultTable& part(const ResultTable<S>& table, G get) {
    for (const auto& p : table.fields()) {
      Field f;
      f.info = p.info;
      f.json = [json = p.json, get](const R& r) { return json(get(r)); };
      if (p.array) f.array = [array = p.array, get](const R& r) { return array(get(r)); };
      fields_.push_back(std::move(f));
    }
    return *this;
  }

  const std::vector<Field>& fields() const { return fields_; }

  //! The named fields of \p r as a caption says them, "mean normal error 2.81 deg, ev relative 0.000992"
  //! (figure_text, in the order asked): the demo's captions use the report's names (std::logic_error for a
  //! name the table does not have).
  std::string figures(const R& r, std::initializer_list<std::string_view> names) const {
    std::string out;
    for (std::string_view name : names) {
      const auto f = std::find_if(fields_.begin(), fields_.end(), [&](const Field& x) { return x.info.name == name; });
      if (f == fields_.end()) throw std::logic_error("no result field named " + std::string(name));
      out += (out.empty() ? "" : ", ") + figure_text(f->info, f->json(r));
    }
    return out;
  }

  //! The fields of the CLI's report, as a JSON object.
  nlohmann::json report(const R& r) const {
    nlohmann::json j = nlohmann::json::object();
    for (const Field& f : fields_)
      if (f.info.in_report) j[f.info.name] = f.json(r);
    return j;
  }

 private:
  template <class T>
  struct is_optional : std::false_type {};
  template <class T>
  struct is_optional<std::optional<T>> : std::true_type {};

  template <class T>
  static constexpr ResultKind kind_of() {
    if constexpr (std::is_same_v<T, bool>) return ResultKind::Bool;
    else if constexpr (std::is_integral_v<T>) return ResultKind::Int;
    else if constexpr (std::is_floating_point_v<T>) return ResultKind::Real;
    else if constexpr (std::is_same_v<T, std::string>) return ResultKind::Text;
    else if constexpr (std::is_same_v<T, std::vector<std::string>>) return ResultKind::Texts;
    else if constexpr (std::is_same_v<T, std::vector<double>>) return ResultKind::Reals;
    else if constexpr (std::is_same_v<T, std::vector<int>>) return ResultKind::Ints;
    else if constexpr (std::is_same_v<T, nlohmann::json>) return ResultKind::Record;
    else static_assert(sizeof(T) == 0, "a result field of an unsupported type (use array() for Eigen types)");
  }

  std::vector<Field> fields_;
};

//! What a front end adds to a result it timed (the CLI and Python time the same library call).
struct RunTime {
  double seconds = 0;  //!< wall time of the library call
};
const ResultTable<RunTime>& run_time_results();

struct MeshSummary;  // core/geometry.h
//! summarize()'s counts and measures: what `geotex info --json` and Python's info() say of a mesh.
const ResultTable<MeshSummary>& mesh_summary_results();

struct ReadReport;  // core/io.h
//! What a reader counted and repaired in a file: `geotex info --json`'s "read" record and the demo's captions.
const ResultTable<ReadReport>& read_report_results();

}  // namespace geotex
