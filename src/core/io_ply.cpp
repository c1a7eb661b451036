// PLY files (io.h): the header, ascii and binary bodies of any element and property types, triangle strips,
// and the writer of vertex and face properties. The scanning helpers are shared with the other formats
// (io_detail.h).

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/core/resources.h"
#include "io_detail.h"

namespace geotex {

namespace fs = std::filesystem;
using namespace detail;

namespace {

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

PlyType ply_type(const fs::path& path, std::string_view t) {
  if (t == "char" || t == "int8") return PlyType::I8;
  if (t == "uchar" || t == "uint8") return PlyType::U8;
  if (t == "short" || t == "int16") return PlyType::I16;
  if (t == "ushort" || t == "uint16") return PlyType::U16;
  if (t == "int" || t == "int32") return PlyType::I32;
  if (t == "uint" || t == "uint32") return PlyType::U32;
  if (t == "float" || t == "float32") return PlyType::F32;
  if (t == "double" || t == "float64") return PlyType::F64;
  throw IoError(fmt::format("{}: unknown PLY property type '{}'", path.string(), t));
}

const char* type_name(PlyType t) {
  switch (t) {
    case PlyType::I8: return "char";
    case PlyType::U8: return "uchar";
    case PlyType::I16: return "short";
    case PlyType::U16: return "ushort";
    case PlyType::I32: return "int";
    case PlyType::U32: return "uint";
    case PlyType::F32: return "float";
    case PlyType::F64: return "double";
  }
  return "?";
}

bool is_integer_type(PlyType t) { return t != PlyType::F32 && t != PlyType::F64; }

// The range of an integer PLY type.
std::pair<int64_t, int64_t> integer_range(PlyType t) {
  switch (t) {
    case PlyType::I8: return {INT8_MIN, INT8_MAX};
    case PlyType::U8: return {0, UINT8_MAX};
    case PlyType::I16: return {INT16_MIN, INT16_MAX};
    case PlyType::U16: return {0, UINT16_MAX};
    case PlyType::I32: return {INT32_MIN, INT32_MAX};
    case PlyType::U32: return {0, UINT32_MAX};
    default: return {0, 0};
  }
}

// One ascii PLY value of type \p t: an integer type holds an integer in its range ("1.5" or 300 in a
// uchar is refused, not truncated or wrapped).
bool parse_ply_ascii(std::string_view tok, PlyType t, double& out) {
  if (!is_integer_type(t)) return parse_double(tok, out);
  int64_t i;
  if (!parse_int64(tok, i)) return false;
  const auto [lo, hi] = integer_range(t);
  if (i < lo || i > hi) return false;
  out = static_cast<double>(i);
  return true;
}

std::string ascii_value_error(std::string_view tok, PlyType t) {
  if (tok.empty()) return "row has too few values (truncated?)";
  if (!is_integer_type(t)) return fmt::format("'{}' is not a number", tok);
  const auto [lo, hi] = integer_range(t);
  return fmt::format("'{}' is not an integer in [{}, {}] (the header declares '{}')", tok, lo, hi, type_name(t));
}

size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::I8: case PlyType::U8: return 1;
    case PlyType::I16: case PlyType::U16: return 2;
    case PlyType::I32: case PlyType::U32: case PlyType::F32: return 4;
    case PlyType::F64: return 8;
  }
  return 0;
}

struct PlyPropDecl {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::U8;
  PlyType type = PlyType::F32;
};

struct PlyElemDecl {
  std::string name;
  size_t count = 0;
  std::vector<PlyPropDecl> props;
};

template <class T>
T load(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

double load_as_double(const char* p, PlyType t, bool swap) {
  switch (t) {
    case PlyType::I8: return load<int8_t>(p, swap);
    case PlyType::U8: return load<uint8_t>(p, swap);
    case PlyType::I16: return load<int16_t>(p, swap);
    case PlyType::U16: return load<uint16_t>(p, swap);
    case PlyType::I32: return load<int32_t>(p, swap);
    case PlyType::U32: return load<uint32_t>(p, swap);
    case PlyType::F32: return load<float>(p, swap);
    case PlyType::F64: return load<double>(p, swap);
  }
  return 0;
}

// The header of a PLY file: its format (into \p format) and its element declarations; leaves \p lr at
// the body's first byte.
std::vector<PlyElemDecl> parse_ply_header(const fs::path& path, std::string_view data, LineReader& lr,
                                          std::string& format) {
  std::string_view line;
  if (!lr.next(line) || line != "ply") throw IoError(fmt::format("{}: not a PLY file (no 'ply' magic)", path.string()));
  // The magic line's end tells how the header's lines end; it decides where a binary body starts
  // after "end_header\r" (a lone CR, then maybe a body byte 0x0A, or CRLF).
  const bool cr_only = data.size() > 3 && data[3] == '\r' && (data.size() == 4 || data[4] != '\n');
  // A header cut short would otherwise be reported by whichever line the cut made malformed.
  if (data.find("end_header") == std::string_view::npos)
    throw IoError(fmt::format("{}: PLY header has no end_header (truncated?)", path.string()));
  std::vector<PlyElemDecl> decls;
  bool header_done = false;
  while (lr.next(line)) {
    std::string_view rest = line;
    const auto key = next_token(rest);
    if (key == "format") {
      format = std::string(next_token(rest));
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        malformed(path, lr.line_no, fmt::format("unknown PLY format '{}'", format));
    } else if (key == "comment" || key == "obj_info" || key.empty()) {
      continue;
    } else if (key == "element") {
      PlyElemDecl d;
      d.name = std::string(next_token(rest));
      int64_t n;
      if (d.name.empty() || !parse_int64(next_token(rest), n) || n < 0)
        malformed(path, lr.line_no, "bad element declaration");
      for (const auto& other : decls)
        if (other.name == d.name) malformed(path, lr.line_no, fmt::format("element '{}' is declared twice", d.name));
      d.count = static_cast<size_t>(n);
      decls.push_back(d);
    } else if (key == "property") {
      if (decls.empty()) malformed(path, lr.line_no, "property before any element");
      PlyPropDecl p;
      const auto t = next_token(rest);
      if (t == "list") {
        p.is_list = true;
        p.count_type = ply_type(path, next_token(rest));
        p.type = ply_type(path, next_token(rest));
      } else {
        p.type = ply_type(path, t);
      }
      p.name = std::string(next_token(rest));
      if (p.name.empty()) malformed(path, lr.line_no, "property without a name");
      for (const auto& other : decls.back().props)
        if (other.name == p.name)  // the values would interleave: x1 x2 of one vertex read as x of two
          malformed(path, lr.line_no,
                    fmt::format("property '{}' of element '{}' is declared twice", p.name, decls.back().name));
      decls.back().props.push_back(p);
    } else if (key == "end_header") {
      header_done = true;
      // Where the body starts: right after this line's end, reading a CR LF pair as one end only if
      // the header's lines end that way.
      size_t body = static_cast<size_t>(line.data() - data.data()) + line.size();
      if (body < data.size() && data[body] == '\n') ++body;
      else if (body < data.size() && data[body] == '\r')
        body += (!cr_only && body + 1 < data.size() && data[body + 1] == '\n') ? 2 : 1;
      lr.pos = body;
      break;
    } else {
      malformed(path, lr.line_no, fmt::format("unexpected header line '{}'", line));
    }
  }
  if (!header_done) throw IoError(fmt::format("{}: PLY header has no end_header (truncated?)", path.string()));
  if (format.empty()) throw IoError(fmt::format("{}: PLY header has no format line", path.string()));
  return decls;
}

// The memory the declared counts need, once they fit in the file (a count the file cannot hold is a
// truncated file, said when its element is read). A strip holds at least one triangle.
void require_ply_memory(const fs::path& path, const std::vector<PlyElemDecl>& decls, std::string_view data,
                        size_t body) {
  size_t nv = 0, nf = 0;
  bool fits = true;
  for (const auto& d : decls) {
    if (d.name == "vertex") nv += d.count;
    if (d.name == "face" || d.name == "tristrips") nf += d.count;
    fits = fits && d.count <= data.size() - std::min(body, data.size()) + 1;
  }
  if (fits) require_memory(fmt::format("{}: reading {} faces and {} vertices", path.string(), nf, nv), mesh_read_bytes(nf, nv));
}

[[noreturn]] void ply_truncated(const fs::path& path, const PlyElemDecl& d, size_t row) {
  throw IoError(fmt::format("{}: truncated: element '{}' declares {} rows, the file ends in row {}",
                            path.string(), d.name, d.count, row));
}

// The rows of element \p d in an ascii body, from \p body on; \p scal and \p lst: where each property's
// values go (one of the two per property).
void read_ply_ascii_rows(const fs::path& path, std::string_view data, const PlyElemDecl& d,
                         const std::vector<std::vector<double>*>& scal, const std::vector<PlyList*>& lst,
                         LineReader& body) {
  for (size_t r = 0; r < d.count; ++r) {
    std::string_view row;
    do {
      if (!body.next(row)) ply_truncated(path, d, r);
    } while ([&] { std::string_view probe = row; return next_token(probe).empty(); }());
    for (size_t k = 0; k < d.props.size(); ++k) {
      const auto& p = d.props[k];
      auto tok = next_token(row);
      if (p.is_list) {
        // A float count type takes any number: only a whole one that the row could hold is a count
        // (casting 9.2e18 to int64 is undefined, truncating 2.5 silently wrong).
        double nd;
        if (!parse_ply_ascii(tok, p.count_type, nd) || !(nd >= 0) || nd != std::floor(nd) ||
            nd > static_cast<double>(data.size()))
          malformed(path, body.line_no, fmt::format("bad list length '{}' (the header declares '{}')", tok,
                                                    type_name(p.count_type)));
        const auto n = static_cast<int64_t>(nd);
        for (int64_t i = 0; i < n; ++i) {
          double v;
          tok = next_token(row);
          if (tok.empty()) malformed(path, body.line_no, fmt::format("list of {} items has fewer (truncated?)", n));
          if (!parse_ply_ascii(tok, p.type, v)) malformed(path, body.line_no, ascii_value_error(tok, p.type));
          lst[k]->items.push_back(v);
        }
        lst[k]->offsets.push_back(static_cast<int64_t>(lst[k]->items.size()));
      } else {
        double v;
        if (!parse_ply_ascii(tok, p.type, v)) malformed(path, body.line_no, ascii_value_error(tok, p.type));
        scal[k]->push_back(v);
      }
    }
  }
}

// The rows of element \p d in a binary body, from byte \p pos on (left after them); \p swap: the
// file's byte order is not the machine's.
void read_ply_binary_rows(const fs::path& path, std::string_view data, const PlyElemDecl& d,
                          const std::vector<std::vector<double>*>& scal, const std::vector<PlyList*>& lst, bool swap,
                          size_t& pos) {
  for (size_t r = 0; r < d.count; ++r) {
    for (size_t k = 0; k < d.props.size(); ++k) {
      const auto& p = d.props[k];
      if (p.is_list) {
        const size_t cs = type_size(p.count_type);
        if (pos + cs > data.size()) ply_truncated(path, d, r);
        const double nd = load_as_double(data.data() + pos, p.count_type, swap);
        pos += cs;
        if (!(nd >= 0) || nd > static_cast<double>(data.size()) || nd != std::floor(nd))
          throw IoError(fmt::format("{}: bad list length {} in element '{}' row {}", path.string(), nd, d.name, r));
        const size_t n = static_cast<size_t>(nd);
        const size_t is = type_size(p.type);
        if (pos + n * is > data.size()) ply_truncated(path, d, r);
        for (size_t i = 0; i < n; ++i, pos += is)
          lst[k]->items.push_back(load_as_double(data.data() + pos, p.type, swap));
        lst[k]->offsets.push_back(static_cast<int64_t>(lst[k]->items.size()));
      } else {
        const size_t is = type_size(p.type);
        if (pos + is > data.size()) ply_truncated(path, d, r);
        scal[k]->push_back(load_as_double(data.data() + pos, p.type, swap));
        pos += is;
      }
    }
  }
}
}  // namespace

namespace detail {

PlyData parse_ply(const fs::path& path, std::string_view data) {
  data = without_bom(data);
  LineReader lr{data};
  PlyData out;
  const std::vector<PlyElemDecl> decls = parse_ply_header(path, data, lr, out.format);
  require_ply_memory(path, decls, data, lr.pos);
  const bool ascii = out.format == "ascii";
  const bool swap = (out.format == "binary_big_endian") == (std::endian::native == std::endian::little);
  size_t pos = lr.pos;
  for (const auto& d : decls) {
    PlyElement el;
    el.name = d.name;
    el.count = d.count;
    if (d.props.empty()) {  // rows without properties take no bytes; don't loop over them
      out.elements.push_back(std::move(el));
      continue;
    }
    // Guard against absurd counts before allocating: every row takes at least one byte.
    if (d.count > data.size() - std::min(pos, data.size()) + 1)
      throw IoError(fmt::format("{}: truncated: element '{}' declares {} rows, the file is too short",
                                path.string(), d.name, d.count));
    for (const auto& p : d.props) {
      el.order.push_back(p.name);
      if (p.is_list) {
        el.lists[p.name].offsets.reserve(d.count + 1);
      } else {
        el.scalars[p.name].reserve(d.count);
      }
    }
    std::vector<std::vector<double>*> scal(d.props.size(), nullptr);
    std::vector<PlyList*> lst(d.props.size(), nullptr);
    for (size_t k = 0; k < d.props.size(); ++k) {
      if (d.props[k].is_list) lst[k] = &el.lists[d.props[k].name];
      else scal[k] = &el.scalars[d.props[k].name];
    }
    if (ascii) {
      LineReader body{data};
      body.pos = pos;
      body.line_no = lr.line_no;
      read_ply_ascii_rows(path, data, d, scal, lst, body);
      pos = body.pos;
      lr.line_no = body.line_no;
    } else {
      read_ply_binary_rows(path, data, d, scal, lst, swap, pos);
    }
    out.elements.push_back(std::move(el));
  }
  return out;
}

Soup soup_from_ply(const fs::path& path, const PlyData& ply, ReadReport& rep) {
  const PlyElement* vert = ply.find("vertex");
  if (!vert) throw IoError(fmt::format("{}: PLY file has no 'vertex' element", path.string()));
  for (const char* c : {"x", "y", "z"})
    if (!vert->scalars.count(c))
      throw IoError(fmt::format("{}: PLY vertex element has no '{}' property", path.string(), c));
  Soup soup;
  const auto &X = vert->scalars.at("x"), &Y = vert->scalars.at("y"), &Z = vert->scalars.at("z");
  soup.xyz.resize(3 * vert->count);
  for (size_t i = 0; i < vert->count; ++i) {
    soup.xyz[3 * i] = X[i];
    soup.xyz[3 * i + 1] = Y[i];
    soup.xyz[3 * i + 2] = Z[i];
  }
  rep.file_vertices = vert->count;
  auto index_list = [&](const PlyElement& e) -> const PlyList* {
    for (const char* n : {"vertex_indices", "vertex_index"})
      if (e.lists.count(n)) return &e.lists.at(n);
    return nullptr;
  };
  if (const PlyElement* face = ply.find("face")) {
    const PlyList* L = index_list(*face);
    if (!L) throw IoError(fmt::format("{}: PLY face element has no vertex_indices list", path.string()));
    std::vector<int64_t> poly;
    for (size_t f = 0; f < L->rows(); ++f) {
      poly.resize(static_cast<size_t>(L->offsets[f + 1] - L->offsets[f]));
      for (size_t k = 0; k < poly.size(); ++k) {
        const double v = L->items[L->offsets[f] + k];
        if (!integral_index(v, poly[k]))
          throw IoError(fmt::format("{}: face {} has vertex index {}, not an integer index", path.string(), f,
                                    detail::exact_number(v)));
      }
      soup.add_polygon(poly.data(), poly.size());
    }
    rep.file_polygons += face->count;
  }
  if (const PlyElement* strips = ply.find("tristrips")) {
    // Triangle strips: consecutive triples, orientation alternating; -1 restarts a strip.
    const PlyList* L = index_list(*strips);
    if (!L) throw IoError(fmt::format("{}: PLY tristrips element has no vertex_indices list", path.string()));
    for (size_t s = 0; s < L->rows(); ++s) {
      std::vector<int64_t> run;
      auto flush = [&]() {
        for (size_t k = 0; k + 2 < run.size(); ++k) {
          int64_t t[3] = {run[k], run[k + 1], run[k + 2]};
          if (k % 2 == 1) std::swap(t[0], t[1]);
          if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // strip padding, not a face
          soup.add_polygon(t, 3);
          ++rep.strip_triangles;
        }
        run.clear();
      };
      for (int64_t i = L->offsets[s]; i < L->offsets[s + 1]; ++i) {
        int64_t v;
        if (!integral_index(L->items[i], v))
          throw IoError(fmt::format("{}: triangle strip {} has vertex index {}, not an integer index", path.string(), s,
                                    detail::exact_number(L->items[i])));
        if (v < 0) flush();
        else run.push_back(v);
      }
      flush();
    }
    rep.file_polygons += strips->count;
    rep.notes.push_back(fmt::format("decoded {} triangle(s) from {} triangle strip(s)",
                                       rep.strip_triangles, strips->count));
  }
  rep.format = "ply (" + ply.format + ")";
  return soup;
}


std::string ply_bytes(const Mesh& mesh, const PlyExtras& extras, bool binary, const fs::path& path) {
  const size_t nv = mesh.n_vertices();
  for (const auto& [name, vals] : extras.vertex_scalars) {
    if (vals.size() != nv)
      throw InvalidInput(fmt::format("PLY vertex property '{}' has {} values for {} vertices", name, vals.size(), nv));
    require_finite_values(vals.data(), vals.size(), fmt::format("'{}' of vertex", name), path);
  }
  for (const auto& e : extras.elements)
    for (const auto& [name, v] : e.double_props)
      require_finite_values(v.data(), v.size(), fmt::format("'{}' of {}", name, e.name), path);
  std::string s = "ply\n";
  s += binary ? (std::endian::native == std::endian::little ? "format binary_little_endian 1.0\n"
                                                            : "format binary_big_endian 1.0\n")
              : "format ascii 1.0\n";
  s += "comment written by geotex\n";
  s += fmt::format("element vertex {}\nproperty double x\nproperty double y\nproperty double z\n", nv);
  for (const auto& [name, vals] : extras.vertex_scalars) s += fmt::format("property double {}\n", name);
  s += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", mesh.n_faces());
  std::vector<size_t> counts;
  for (const auto& e : extras.elements) {
    size_t n = std::string::npos;
    for (const auto& [name, v] : e.int_props) n = std::min(n, v.size());
    for (const auto& [name, v] : e.double_props) n = std::min(n, v.size());
    if (n == std::string::npos) n = 0;
    for (const auto& [name, v] : e.int_props)
      if (v.size() != n) throw InvalidInput(fmt::format("PLY element '{}': property '{}' has a different length", e.name, name));
    for (const auto& [name, v] : e.double_props)
      if (v.size() != n) throw InvalidInput(fmt::format("PLY element '{}': property '{}' has a different length", e.name, name));
    counts.push_back(n);
    s += fmt::format("element {} {}\n", e.name, n);
    for (const auto& [name, v] : e.int_props) s += fmt::format("property int {}\n", name);
    for (const auto& [name, v] : e.double_props) s += fmt::format("property double {}\n", name);
  }
  s += "end_header\n";
  s.reserve(s.size() + nv * (24 + 8 * extras.vertex_scalars.size()) + mesh.n_faces() * 13);
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (binary) {
      for (int k = 0; k < 3; ++k) append_bin<double>(s, p[k]);
      for (const auto& [name, vals] : extras.vertex_scalars) append_bin<double>(s, vals[v.idx()]);
    } else {
      append_double(s, p[0]); s += ' ';
      append_double(s, p[1]); s += ' ';
      append_double(s, p[2]);
      for (const auto& [name, vals] : extras.vertex_scalars) { s += ' '; append_double(s, vals[v.idx()]); }
      s += '\n';
    }
  }
  for (auto f : mesh.faces()) {
    if (binary) {
      append_bin<uint8_t>(s, 3);
      for (auto v : f.vertices()) append_bin<int32_t>(s, v.idx());
    } else {
      s += '3';
      for (auto v : f.vertices()) { s += ' '; append_int(s, v.idx()); }
      s += '\n';
    }
  }
  for (size_t ei = 0; ei < extras.elements.size(); ++ei) {
    const auto& e = extras.elements[ei];
    for (size_t r = 0; r < counts[ei]; ++r) {
      bool first = true;
      for (const auto& [name, v] : e.int_props) {
        if (binary) append_bin<int32_t>(s, v[r]);
        else { if (!first) s += ' '; append_int(s, v[r]); }
        first = false;
      }
      for (const auto& [name, v] : e.double_props) {
        if (binary) append_bin<double>(s, v[r]);
        else { if (!first) s += ' '; append_double(s, v[r]); }
        first = false;
      }
      if (!binary) s += '\n';
    }
  }
  return s;
}

}  // namespace detail

const PlyElement* PlyData::find(const std::string& name) const {
  for (const auto& e : elements)
    if (e.name == name) return &e;
  return nullptr;
}

PlyData read_ply_data(const fs::path& path) {
  const std::string data = read_file_bytes(path);
  return parse_ply(path, data);
}

PlyData parse_ply_bytes(std::string_view data, const std::string& name) { return parse_ply(fs::path(name), data); }

}  // namespace geotex
