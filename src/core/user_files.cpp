// Readers of the small user files besides meshes: deformation handles (JSON), feature weights, point clouds.

#include "geotex/core/user_files.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {
namespace fs = std::filesystem;

namespace {

using json = nlohmann::json;

// Only regular files, up to a limit (read_regular_file in io.h): a FIFO or /dev/zero is refused at once.
std::string read_text(const fs::path& path, size_t max_bytes, const char* what) {
  return read_regular_file(path, max_bytes, what);
}

// A UTF-8 byte order mark (some Windows editors write one) is not part of the text.
std::string_view without_bom(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

std::string lower_extension(const fs::path& path) {
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// Lines of a text (after any byte order mark), without their end: LF, CRLF or a lone CR.
template <class F>
void for_each_line(std::string_view text, F&& f) {
  text = without_bom(text);
  size_t line_no = 0;
  while (!text.empty()) {
    const size_t end = text.find_first_of("\r\n");
    f(text.substr(0, end), ++line_no);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + (text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n' ? 2 : 1));
  }
}

// A finite number: the whole token (strtod syntax, no trailing characters).
bool parse_double(std::string_view token, double& v) {
  if (token.empty()) return false;
  const std::string s(token);
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

// Whitespace-separated tokens of a line.
std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

Vec3 vec3(const json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw InvalidInput(fmt::format("{} must be an array of three numbers", what));
  const Vec3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  if (!v.allFinite()) throw InvalidInput(fmt::format("{} must be finite", what));
  return v;
}

double number(const json& j, const std::string& what) {
  if (!j.is_number()) throw InvalidInput(fmt::format("{} must be a number", what));
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw InvalidInput(fmt::format("{} must be finite", what));
  return v;
}

const json& member(const json& j, const char* key, const std::string& what) {
  if (!j.is_object()) throw InvalidInput(fmt::format("{} must be an object", what));
  if (!j.contains(key)) throw InvalidInput(fmt::format("{} needs \"{}\"", what, key));
  return j[key];
}

// Vertex ids of one handle: "vertices", "sphere" or "box".
std::vector<int> select_vertices(const json& h, const MatrixX3d& X, const std::string& where) {
  const int64_t n = X.rows();
  std::vector<int> ids;
  if (h.contains("vertices")) {
    const json& vs = h["vertices"];
    if (!vs.is_array()) throw InvalidInput(where + ": \"vertices\" must be an array of vertex ids");
    for (const json& v : vs) {
      if (!v.is_number_integer()) throw InvalidInput(fmt::format("{}: vertex id {} is not an integer", where, v.dump()));
      // Unsigned values beyond int64 are out of range too (get<int64_t> would wrap them).
      const bool too_big = v.is_number_unsigned() && v.get<uint64_t>() >= static_cast<uint64_t>(n);
      const int64_t id = too_big ? n : v.get<int64_t>();
      if (id < 0 || id >= n) throw InvalidInput(fmt::format("{}: vertex {} is out of range [0, {})", where, v.dump(), n));
      ids.push_back(static_cast<int>(id));
    }
  } else if (h.contains("sphere")) {
    const json& s = h["sphere"];
    const Vec3 c = vec3(member(s, "center", where + " sphere"), where + " sphere.center");
    const double r = number(member(s, "radius", where + " sphere"), where + " sphere.radius");
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if ((X.row(i).transpose() - c).norm() <= r) ids.push_back(static_cast<int>(i));
  } else {
    const json& b = h["box"];
    const Vec3 lo = vec3(member(b, "min", where + " box"), where + " box.min");
    const Vec3 hi = vec3(member(b, "max", where + " box"), where + " box.max");
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      const Vec3 p = X.row(i).transpose();
      if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) ids.push_back(static_cast<int>(i));
    }
  }
  return ids;
}

// Targets of one handle's vertices: explicit "targets", or the transform x ↦ R(s (x − c)) + c + t.
void handle_targets(const json& h, const MatrixX3d& X, const std::vector<int>& ids, const std::string& where,
                    std::vector<Vec3>& targets) {
  if (h.contains("targets")) {
    if (!h.contains("vertices")) throw InvalidInput(where + ": \"targets\" needs \"vertices\"");
    const json& t = h["targets"];
    if (!t.is_array() || t.size() != ids.size())
      throw InvalidInput(fmt::format("{}: {} targets for {} vertices", where, t.is_array() ? t.size() : 0, ids.size()));
    for (const json& p : t) targets.push_back(vec3(p, where + " target"));
    return;
  }
  Vec3 c = Vec3::Zero();
  for (int i : ids) c += X.row(i).transpose();
  c /= static_cast<double>(ids.size());
  if (h.contains("center")) c = vec3(h["center"], where + " center");
  const double s = h.contains("scale") ? number(h["scale"], where + " scale") : 1.0;
  if (!(s > 0)) throw InvalidInput(where + ": scale must be positive");
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Vec3 rc = c;
  if (h.contains("rotate")) {
    const json& r = h["rotate"];
    const Vec3 axis = vec3(member(r, "axis", where + " rotate"), where + " rotate.axis");
    if (axis.norm() == 0) throw InvalidInput(where + ": rotation axis is zero");
    const double angle = number(member(r, "angle_deg", where + " rotate"), where + " rotate.angle_deg");
    R = Eigen::AngleAxisd(angle * M_PI / 180.0, axis.normalized()).toRotationMatrix();
    if (r.contains("center")) rc = vec3(r["center"], where + " rotate.center");
  }
  const Vec3 t = h.contains("translate") ? vec3(h["translate"], where + " translate") : Vec3::Zero();
  for (int i : ids) {
    const Vec3 scaled = c + s * (X.row(i).transpose() - c);
    const Vec3 y = rc + R * (scaled - rc) + t;
    if (!y.allFinite()) throw InvalidInput(where + ": the transform gives a non-finite target");
    targets.push_back(y);
  }
}

}  // namespace

void require_unit_weights(const Eigen::VectorXd& w, const std::string& name) {
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (!(w[i] >= 0 && w[i] <= 1))
      throw InvalidInput(fmt::format("{}: feature weight {} of vertex {} is not in [0, 1]", name, w[i], i));
}

// ---------------------------------------------------------------------------------------------

HandleSet parse_handles(std::string_view json_text, const MatrixX3d& X, double default_weight, const std::string& name) {
  json doc;
  try {
    doc = json::parse(json_text.begin(), json_text.end());
  } catch (const json::exception& e) {
    throw IoError(fmt::format("{}: not valid JSON ({})", name, e.what()));
  }
  if (!doc.is_object() || !doc.contains("handles") || !doc["handles"].is_array() || doc["handles"].empty())
    throw InvalidInput(fmt::format("{}: expected {{\"handles\": [ ... ]}} with at least one handle", name));
  HandleSet out;
  std::vector<Vec3> targets;
  std::vector<int> owner(X.rows(), -1);  // which handle selected each vertex
  int index = 0;
  try {
    for (const json& h : doc["handles"]) {
      const std::string where = fmt::format("{}: handle {}", name, index);
      if (!h.is_object()) throw InvalidInput(where + " is not an object");
      const int selectors = h.contains("vertices") + h.contains("sphere") + h.contains("box");
      if (selectors != 1) throw InvalidInput(where + " needs exactly one of \"vertices\", \"sphere\", \"box\"");
      const std::vector<int> ids = select_vertices(h, X, where);
      if (ids.empty()) throw InvalidInput(where + " selects no vertices");
      for (int i : ids) {
        if (owner[i] >= 0)
          throw InvalidInput(fmt::format("{}: vertex {} is already a handle vertex (handle {})", where, i, owner[i]));
        owner[i] = index;
      }
      const double w = h.contains("weight") ? number(h["weight"], where + " weight") : default_weight;
      if (!(w > 0)) throw InvalidInput(where + ": weight must be positive");
      handle_targets(h, X, ids, where, targets);
      out.ids.insert(out.ids.end(), ids.begin(), ids.end());
      out.weights.insert(out.weights.end(), ids.size(), w);
      ++index;
    }
  } catch (const json::exception& e) {  // a type mismatch the checks above did not foresee
    throw InvalidInput(fmt::format("{}: handle {}: {}", name, index, e.what()));
  }
  out.targets.resize(static_cast<Eigen::Index>(targets.size()), 3);
  for (size_t k = 0; k < targets.size(); ++k) out.targets.row(static_cast<Eigen::Index>(k)) = targets[k].transpose();
  return out;
}

HandleSet read_handles(const fs::path& path, const MatrixX3d& X, double default_weight) {
  return parse_handles(read_text(path, kMaxHandlesFileBytes, "a handles file"), X, default_weight, path.string());
}

// ---------------------------------------------------------------------------------------------

Eigen::VectorXd parse_feature_weights(std::string_view text, size_t n_vertices, const std::string& name) {
  std::vector<double> w;
  for_each_line(text, [&](std::string_view line, size_t line_no) {
    const auto t = tokens(line);
    if (t.empty() || t[0][0] == '#') return;
    double v;
    if (t.size() != 1 || !parse_double(t[0], v))
      throw IoError(fmt::format("{}:{}: not a finite number: {}", name, line_no, std::string(line.substr(0, 80))));
    w.push_back(v);
  });
  if (w.size() != n_vertices)
    throw InvalidInput(fmt::format("{}: {} feature weights for {} vertices", name, w.size(), n_vertices));
  Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
  require_unit_weights(out, name);
  return out;
}

// ---------------------------------------------------------------------------------------------

MatrixX3d parse_point_text(std::string_view text, bool obj, const std::string& name) {
  std::vector<Vec3> pts;
  for_each_line(text, [&](std::string_view line, size_t line_no) {
    auto t = tokens(line);
    if (obj) {
      if (t.empty() || t[0] != "v") return;
      t.erase(t.begin());
    } else if (t.empty() || t[0][0] == '#') {
      return;
    }
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      // Non-finite values are numbers here (reported below as InvalidInput); only junk is an IoError.
      const std::string s = k < static_cast<int>(t.size()) ? std::string(t[k]) : std::string();
      char* end = nullptr;
      p[k] = std::strtod(s.c_str(), &end);
      if (s.empty() || end != s.c_str() + s.size())
        throw IoError(fmt::format("{}:{}: expected three coordinates", name, line_no));
    }
    pts.push_back(p);
  });
  if (pts.empty()) throw InvalidInput(fmt::format("{}: no points", name));
  MatrixX3d P(static_cast<Eigen::Index>(pts.size()), 3);
  for (size_t i = 0; i < pts.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
  if (!P.allFinite()) throw InvalidInput(fmt::format("{}: non-finite coordinate", name));
  return P;
}

MatrixX3d points_from_ply(const PlyData& ply, const std::string& name) {
  const PlyElement* v = ply.find("vertex");
  if (!v || !v->scalars.count("x") || !v->scalars.count("y") || !v->scalars.count("z"))
    throw IoError(fmt::format("{}: no vertex element with x, y, z", name));
  const auto &x = v->scalars.at("x"), &y = v->scalars.at("y"), &z = v->scalars.at("z");
  if (x.size() != v->count || y.size() != v->count || z.size() != v->count)
    throw IoError(fmt::format("{}: x, y, z must each be declared once", name));
  if (v->count == 0) throw InvalidInput(fmt::format("{}: no points", name));
  MatrixX3d P(static_cast<Eigen::Index>(v->count), 3);
  for (size_t i = 0; i < v->count; ++i) P.row(static_cast<Eigen::Index>(i)) << x[i], y[i], z[i];
  if (!P.allFinite()) throw InvalidInput(fmt::format("{}: non-finite coordinate", name));
  return P;
}

bool is_point_file(const fs::path& path) {
  const std::string e = lower_extension(path);
  return e == ".ply" || e == ".obj" || e == ".xyz" || e == ".pts" || e == ".txt";
}

MatrixX3d read_point_file(const fs::path& path) {
  const std::string e = lower_extension(path);
  if (e == ".ply") return points_from_ply(read_ply_data(path), path.string());
  if (!is_point_file(path)) throw IoError(fmt::format("{}: not a point file (.ply .obj .xyz .pts .txt)", path.string()));
  return parse_point_text(read_text(path, kMaxTextFileBytes, "a point file"), e == ".obj", path.string());
}

}  // namespace geotex
