#include "geotex/core/options.h"

#include <cerrno>
#include <cstdlib>

#include <fmt/format.h>

namespace geotex {

namespace {

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{}", v);
}

const char* kind_name(OptionKind k) {
  switch (k) {
    case OptionKind::Bool: return "true or false";
    case OptionKind::Int: return "an integer";
    case OptionKind::Real: return "a number";
    case OptionKind::Text: return "text";
    case OptionKind::Choice: return "a name";
    case OptionKind::Vec3: return "three numbers like 1,0,0";
  }
  return "a value";
}

// Strict number parsing: the whole text, finite (NaN, inf and overflow are refused).
bool parse_real(const std::string& s, double& out) {
  if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && errno != ERANGE && std::isfinite(out);
}

bool parse_int(const std::string& s, int64_t& out) {
  if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end == s.c_str() + s.size() && errno != ERANGE) {
    out = v;
    return true;
  }
  // "1e3" or "5.0": accepted when the number is a whole number within range.
  double d;
  if (!parse_real(s, d) || d != std::floor(d) || std::abs(d) > 9.0e15) return false;
  out = static_cast<int64_t>(d);
  return true;
}

}  // namespace

std::string Bounds::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (!has_lo && !has_hi) return "any finite value";
  if (has_lo && !has_hi) return fmt::format("{} {}", lo_open ? ">" : ">=", number(lo));
  if (!has_lo && has_hi) return fmt::format("{} {}", hi_open ? "<" : "<=", number(hi));
  return fmt::format("in {}{}, {}{}", lo_open ? "(" : "[", number(lo), number(hi), hi_open ? ")" : "]");
}

std::string cli_flag(const std::string& name) {
  std::string f = "--" + name;
  for (char& c : f)
    if (c == '_') c = '-';
  return f;
}

std::string OptionInfo::cli_flag() const { return geotex::cli_flag(name); }

void check_option_value(const OptionInfo& info, const OptionValue& value) {
  const auto bad = [&](const std::string& why) {
    return InvalidOption(fmt::format("option {}: {}", info.name, why));
  };
  if (std::holds_alternative<std::monostate>(value)) {
    if (!info.automatic) throw bad("has no automatic value; give " + std::string(kind_name(info.kind)));
    return;
  }
  const auto in_bounds = [&](double v) {
    if (!std::isfinite(v)) throw bad(fmt::format("{} is not a finite number", number(v)));
    if (!info.bounds.contains(v)) throw bad(fmt::format("{} is out of range (must be {})", number(v), info.bounds.describe()));
  };
  switch (info.kind) {
    case OptionKind::Bool:
      if (!std::holds_alternative<bool>(value)) throw bad("expected true or false");
      return;
    case OptionKind::Int:
      if (!std::holds_alternative<int64_t>(value)) throw bad("expected an integer");
      in_bounds(static_cast<double>(std::get<int64_t>(value)));
      return;
    case OptionKind::Real:
      if (const auto* i = std::get_if<int64_t>(&value)) return in_bounds(static_cast<double>(*i));
      if (!std::holds_alternative<double>(value)) throw bad("expected a number");
      in_bounds(std::get<double>(value));
      return;
    case OptionKind::Text:
      if (!std::holds_alternative<std::string>(value)) throw bad("expected text");
      return;
    case OptionKind::Choice: {
      if (!std::holds_alternative<std::string>(value)) throw bad("expected a name");
      const auto& s = std::get<std::string>(value);
      for (const auto& c : info.choices)
        if (c == s) return;
      throw bad(fmt::format("'{}' is not one of {}", s, fmt::join(info.choices, ", ")));
    }
    case OptionKind::Vec3:
      if (!std::holds_alternative<Vec3>(value)) throw bad("expected three numbers");
      for (int k = 0; k < 3; ++k) in_bounds(std::get<Vec3>(value)[k]);
      return;
  }
}

OptionValue parse_option_value(const OptionInfo& info, const std::string& text) {
  const auto bad = [&] {
    return InvalidOption(fmt::format("option {}: '{}' is not {}{}", info.name, text, kind_name(info.kind),
                                     info.automatic ? " or 'auto'" : ""));
  };
  OptionValue v;
  if (info.automatic && text == "auto") {
    v = std::monostate{};
  } else {
    switch (info.kind) {
      case OptionKind::Bool:
        if (text == "true" || text == "1" || text == "yes" || text == "on") v = true;
        else if (text == "false" || text == "0" || text == "no" || text == "off") v = false;
        else throw bad();
        break;
      case OptionKind::Int: {
        int64_t i;
        if (!parse_int(text, i)) throw bad();
        v = i;
        break;
      }
      case OptionKind::Real: {
        double d;
        if (!parse_real(text, d)) throw bad();
        v = d;
        break;
      }
      case OptionKind::Text:
      case OptionKind::Choice:
        v = text;
        break;
      case OptionKind::Vec3: {
        Vec3 p;
        size_t start = 0;
        for (int k = 0; k < 3; ++k) {
          const size_t comma = text.find(',', start);
          if ((k < 2) != (comma != std::string::npos)) throw bad();
          if (!parse_real(text.substr(start, k < 2 ? comma - start : std::string::npos), p[k])) throw bad();
          start = comma + 1;
        }
        v = p;
        break;
      }
    }
  }
  check_option_value(info, v);
  return v;
}

std::string format_option_value(const OptionValue& value) {
  struct {
    std::string operator()(std::monostate) const { return "auto"; }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return number(d); }
    std::string operator()(const std::string& s) const { return s; }
    std::string operator()(const Vec3& p) const { return fmt::format("{},{},{}", number(p[0]), number(p[1]), number(p[2])); }
  } f;
  return std::visit(f, value);
}

}  // namespace geotex
