#pragma once
//! \file options.h One description per options struct.
//!
//! Every options struct of geotex describes its fields once, in an OptionTable next to its
//! implementation: name, one-line help, valid range or choices, thesis reference. The default is the
//! field's initializer in the struct (typed nowhere else). From that one description
//!  - the CLI makes its flags (`--phi0` for `phi0`, with the default, range and help shown),
//!  - the Python module makes keyword arguments with real signatures and defaults,
//!  - reports list the parameters a run used (values()),
//!  - check() refuses values out of range, NaN and infinity before any work.
//!
//! A table is returned by a static member of its struct, e.g. `MrfOptions::table()`, defined in the
//! topic's .cpp:
//!
//!   const OptionTable<SmoothingOptions>& SmoothingOptions::table() {
//!     static const auto t = OptionTable<SmoothingOptions>()
//!         .add("lambda", &SmoothingOptions::lambda, "step size λ", positive(), "Eq. (5.14)")
//!         .choice("laplacian", &SmoothingOptions::laplacian, {{"umbrella", …}, {"cotan", …}}, "…");
//!     return t;
//!   }
//!
//! Field types: bool, int, uint64_t, double, std::string, Vec3, enums (choice()), std::optional<double>
//! and std::optional<int> ("auto": unset means derived from the input), and nested options structs
//! (nest(), with an optional name prefix). Presets (e.g. "thesis") are named functions on the struct.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "geotex/core/error.h"
#include "geotex/core/mesh.h"

namespace geotex {

//! A bad option value or an unknown option name (the CLI exits with code 2; Python raises ValueError).
class InvalidOption : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

//! The value of one option as front ends see it; std::monostate is "auto" (an unset optional).
using OptionValue = std::variant<std::monostate, bool, int64_t, double, std::string, Vec3>;

enum class OptionKind { Bool, Int, Real, Text, Choice, Vec3 };

//! Valid range of a number (Int, Real, and each component of Vec3). NaN and infinity are always refused.
struct Bounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string describe() const;  //!< "> 0", "in [0, 180]", "any", …
};
inline Bounds any_value() { return {}; }
inline Bounds positive() { return {0, std::numeric_limits<double>::infinity(), true, false}; }
inline Bounds non_negative() { return {0, std::numeric_limits<double>::infinity(), false, false}; }
inline Bounds at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
inline Bounds between(double lo, double hi) { return {lo, hi, false, false}; }
inline Bounds unit_interval() { return between(0, 1); }
inline Bounds angle_deg() { return between(0, 180); }

//! Names of an enum's values, the first name of a value being how it is written; one table per enum,
//! next to the enum (e.g. laplacian_names()), used by options, front ends and reports alike.
template <class E>
using EnumNames = std::vector<std::pair<std::string, E>>;

//! The value named \p text. \throw InvalidOption listing the names, with \p what saying what was parsed.
template <class E>
E parse_enum(const EnumNames<E>& names, const std::string& text, const std::string& what) {
  for (const auto& [n, e] : names)
    if (n == text) return e;
  std::string known;
  for (const auto& [n, e] : names) known += (known.empty() ? "" : ", ") + n;
  throw InvalidOption(what + ": '" + text + "' is not one of " + known);
}
//! The name of \p value (its first name in \p names).
template <class E>
std::string enum_name(const EnumNames<E>& names, E value) {
  for (const auto& [n, e] : names)
    if (e == value) return n;
  return "?";
}

//! Type-erased description of one option, for front ends.
struct OptionInfo {
  std::string name;   //!< snake_case; the CLI flag is --kebab-case
  OptionKind kind = OptionKind::Real;
  std::string help;   //!< one line
  std::string ref;    //!< thesis reference ("Eq. (6.4)", "Sec. 7.4.3.4"); empty when not in the thesis
  Bounds bounds;      //!< Int, Real, Vec3
  std::vector<std::string> choices;  //!< Choice: the accepted names
  bool automatic = false;            //!< may be "auto" (unset: derived from the input)
  //! Other command-line names: (name, "") is another spelling; (name, value) a flag that sets value
  //! (e.g. ("explicit", "false") for the bool "implicit"). Kept for flags older than the table.
  std::vector<std::pair<std::string, std::string>> aliases;
  std::string cli_flag() const;      //!< "--" + name with '_' → '-'
};
//! "--" + \p name with '_' → '-'.
std::string cli_flag(const std::string& name);

//! Parse a value of option \p info from text ("auto", "true"/"false", numbers, "x,y,z", choice names).
//! \throw InvalidOption naming the option.
OptionValue parse_option_value(const OptionInfo& info, const std::string& text);
//! The value as text, the way parse_option_value() reads it ("auto" for unset).
std::string format_option_value(const OptionValue& value);
//! Check a value against its description (kind, range, choice); \throw InvalidOption naming the option.
void check_option_value(const OptionInfo& info, const OptionValue& value);

namespace detail {
template <class T> struct is_optional : std::false_type {};
template <class T> struct is_optional<std::optional<T>> : std::true_type {};
}  // namespace detail

template <class O>
class OptionTable {
 public:
  struct Field {
    OptionInfo info;
    std::function<OptionValue(const O&)> get;
    std::function<void(O&, const OptionValue&)> set;  //!< checks the value first
    //! Sets without checking: for tests handing an entry point a value its table refuses.
    std::function<void(O&, const OptionValue&)> assign;
  };
  struct Preset {
    std::string name, help;
    std::function<void(O&)> apply;  //!< sets the preset's values on top of the defaults
  };

  //! A plain field: bool, int, uint64_t, double, std::string, Vec3, std::optional<double|int>.
  template <class T>
  OptionTable& add(std::string name, T O::*member, std::string help, Bounds bounds = {}, std::string ref = {}) {
    OptionInfo info;
    info.name = std::move(name);
    info.help = std::move(help);
    info.ref = std::move(ref);
    info.bounds = bounds;
    using V = typename std::conditional_t<detail::is_optional<T>::value, T, std::optional<T>>::value_type;
    info.automatic = detail::is_optional<T>::value;
    if constexpr (std::is_same_v<V, bool>) info.kind = OptionKind::Bool;
    else if constexpr (std::is_integral_v<V>) info.kind = OptionKind::Int;
    else if constexpr (std::is_floating_point_v<V>) info.kind = OptionKind::Real;
    else if constexpr (std::is_same_v<V, std::string>) info.kind = OptionKind::Text;
    else if constexpr (std::is_same_v<V, Vec3>) info.kind = OptionKind::Vec3;
    else static_assert(sizeof(V) == 0, "unsupported option type");
    if constexpr (std::is_integral_v<V> && !std::is_same_v<V, bool>) {  // what the field can hold
      info.bounds.lo = std::max(info.bounds.lo, static_cast<double>(std::numeric_limits<V>::min()));
      info.bounds.hi = std::min(info.bounds.hi, static_cast<double>(std::numeric_limits<int64_t>::max() / 2));
      if constexpr (sizeof(V) < sizeof(int64_t))
        info.bounds.hi = std::min(info.bounds.hi, static_cast<double>(std::numeric_limits<V>::max()));
    }
    Field f;
    f.info = info;
    f.get = [member](const O& o) -> OptionValue {
      if constexpr (detail::is_optional<T>::value) {
        if (!(o.*member)) return std::monostate{};
        return to_value(*(o.*member));
      } else {
        return to_value(o.*member);
      }
    };
    f.assign = [member](O& o, const OptionValue& v) {
      if constexpr (detail::is_optional<T>::value) {
        if (std::holds_alternative<std::monostate>(v)) o.*member = std::nullopt;
        else o.*member = from_value<V>(v);
      } else {
        o.*member = from_value<V>(v);
      }
    };
    f.set = [assign = f.assign, info](O& o, const OptionValue& v) {
      check_option_value(info, v);
      assign(o, v);
    };
    fields_.push_back(std::move(f));
    return *this;
  }

  //! An enum field, spelled by \p names (the first name of a value is how it is written back).
  template <class E>
  OptionTable& choice(std::string name, E O::*member, const EnumNames<E>& names, std::string help,
                      std::string ref = {}) {
    OptionInfo info;
    info.name = std::move(name);
    info.kind = OptionKind::Choice;
    info.help = std::move(help);
    info.ref = std::move(ref);
    for (const auto& [n, e] : names)
      if (std::find(info.choices.begin(), info.choices.end(), n) == info.choices.end()) info.choices.push_back(n);
    Field f;
    f.info = info;
    f.get = [member, names](const O& o) -> OptionValue {
      for (const auto& [n, e] : names)
        if (e == o.*member) return n;
      return std::string("?");
    };
    f.assign = [member, names](O& o, const OptionValue& v) {
      const auto& s = std::get<std::string>(v);
      for (const auto& [n, e] : names)
        if (n == s) o.*member = e;
    };
    f.set = [assign = f.assign, info](O& o, const OptionValue& v) {
      check_option_value(info, v);
      assign(o, v);
    };
    fields_.push_back(std::move(f));
    return *this;
  }

  //! The fields of a nested options struct, named \p prefix + their own names.
  template <class S>
  OptionTable& nest(S O::*member, const OptionTable<S>& inner, const std::string& prefix = {}) {
    for (const auto& g : inner.fields()) {
      Field f;
      f.info = g.info;
      f.info.name = prefix + g.info.name;
      f.get = [member, get = g.get](const O& o) { return get(o.*member); };
      f.set = [member, set = g.set](O& o, const OptionValue& v) { set(o.*member, v); };
      f.assign = [member, assign = g.assign](O& o, const OptionValue& v) { assign(o.*member, v); };
      fields_.push_back(std::move(f));
    }
    return *this;
  }

  //! Another command-line name for the field added last (see OptionInfo::aliases).
  OptionTable& alias(std::string name, std::string value = {}) {
    fields_.back().info.aliases.emplace_back(std::move(name), std::move(value));
    return *this;
  }

  //! A named preset, e.g. "thesis": the settings of the thesis' own runs.
  OptionTable& preset(std::string name, std::string help, std::function<void(O&)> apply) {
    presets_.push_back({std::move(name), std::move(help), std::move(apply)});
    return *this;
  }

  const std::vector<Field>& fields() const { return fields_; }
  const std::vector<Preset>& presets() const { return presets_; }

  //! The field called \p name, or nullptr.
  const Field* find(const std::string& name) const {
    for (const auto& f : fields_)
      if (f.info.name == name) return &f;
    return nullptr;
  }
  //! Set option \p name. \throw InvalidOption for an unknown name or a bad value.
  void set(O& o, const std::string& name, const OptionValue& v) const {
    const Field* f = find(name);
    if (!f) throw InvalidOption("unknown option '" + name + "'");
    f->set(o, v);
  }
  //! Apply preset \p name to \p o. \throw InvalidOption for an unknown preset.
  void apply_preset(O& o, const std::string& name) const {
    for (const auto& p : presets_)
      if (p.name == name) return p.apply(o);
    std::string known;
    for (const auto& p : presets_) known += (known.empty() ? "" : ", ") + p.name;
    throw InvalidOption("unknown preset '" + name + "'" + (known.empty() ? " (this method has none)" : " (" + known + ")"));
  }
  //! Every option's value, in table order.
  std::vector<std::pair<std::string, OptionValue>> values(const O& o) const {
    std::vector<std::pair<std::string, OptionValue>> out;
    for (const auto& f : fields_) out.emplace_back(f.info.name, f.get(o));
    return out;
  }
  //! Check every option of \p o (range, NaN, choice). \throw InvalidOption naming the first bad one.
  void check(const O& o) const {
    for (const auto& f : fields_) check_option_value(f.info, f.get(o));
  }

 private:
  template <class V>
  static OptionValue to_value(const V& v) {
    if constexpr (std::is_same_v<V, bool>) return v;
    else if constexpr (std::is_integral_v<V>) return static_cast<int64_t>(v);
    else if constexpr (std::is_floating_point_v<V>) return static_cast<double>(v);
    else return v;
  }
  template <class V>
  static V from_value(const OptionValue& v) {
    if constexpr (std::is_same_v<V, bool>) return std::get<bool>(v);
    else if constexpr (std::is_integral_v<V>) return static_cast<V>(std::get<int64_t>(v));
    else if constexpr (std::is_floating_point_v<V>) {
      if (const auto* i = std::get_if<int64_t>(&v)) return static_cast<V>(*i);
      return static_cast<V>(std::get<double>(v));
    } else return std::get<V>(v);
  }

  std::vector<Field> fields_;
  std::vector<Preset> presets_;
};

//! Check \p o against its table (O::table()). \throw InvalidOption.
template <class O>
void check_options(const O& o) {
  O::table().check(o);
}

}  // namespace geotex
