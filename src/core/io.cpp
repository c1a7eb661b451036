// Mesh file readers and writers. Written here rather than taken from OpenMesh's IO because
// OpenMesh 9 reports partial reads as success, drops faces with only a stderr line, cannot read PLY
// triangle strips or extra PLY elements, and writes text coordinates with 6 digits.

#include "geotex/core/io.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/output.h"
#include "geotex/core/resources.h"
#include "io_detail.h"

namespace geotex {

namespace fs = std::filesystem;

std::string detail::exact_number(double v) {
  // Up to 2^70 the digits are few; fmt's fixed format is exact (no printf-style rounding to 17 digits).
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 0x1p70) return fmt::format("{:.0f}", v);
  return fmt::format("{}", v);
}

// The scanning and writing helpers the format files share (io_detail.h).
namespace detail {


std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string read_file_bytes(const fs::path& path) { return read_regular_file(path); }

std::string human_bytes(uint64_t n) {
  if (n >= (1ull << 30)) return fmt::format("{:.1f} GiB", n / double(1ull << 30));
  if (n >= (1ull << 20)) return fmt::format("{:.1f} MiB", n / double(1ull << 20));
  return fmt::format("{} bytes", n);
}

// ---------------------------------------------------------------------------------------------
// Text scanning helpers.

// A UTF-8 byte order mark, which some Windows tools put before any text.
constexpr std::string_view kBom = "\xEF\xBB\xBF";
std::string_view without_bom(std::string_view data) {
  return data.substr(0, 3) == kBom ? data.substr(3) : data;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Split off the next whitespace-separated token; empty when none is left.
std::string_view next_token(std::string_view& s) {
  size_t i = 0;
  while (i < s.size() && is_space(s[i])) ++i;
  size_t j = i;
  while (j < s.size() && !is_space(s[j])) ++j;
  std::string_view tok = s.substr(i, j - i);
  s.remove_prefix(j);
  return tok;
}

bool parse_double(std::string_view tok, double& out) {
  if (tok.empty()) return false;
  if (tok.front() == '+') tok.remove_prefix(1);
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  if (ec == std::errc::result_out_of_range) {  // denormal or overflow: let strtod decide
    out = std::strtod(std::string(tok).c_str(), nullptr);
    return true;
  }
  if (ec != std::errc() || p != tok.data() + tok.size()) {
    // from_chars does not accept "inf"/"nan" spelled with case variants other tools write.
    const std::string t = lower(std::string(tok));
    if (t == "nan" || t == "-nan" || t == "inf" || t == "-inf" || t == "infinity" || t == "-infinity") {
      out = std::strtod(t.c_str(), nullptr);
      return true;
    }
    return false;
  }
  return true;
}

bool parse_int64(std::string_view tok, int64_t& out) {
  if (tok.empty()) return false;
  if (tok.front() == '+') tok.remove_prefix(1);
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && p == tok.data() + tok.size();
}

[[noreturn]] void malformed(const fs::path& path, size_t line, const std::string& what) {
  throw IoError(fmt::format("{}:{}: {}", path.string(), line, what));
}

// A vertex index stored as a number of any type: an integer within int range (casting anything else
// is undefined behaviour, and truncating 2.5 to 2 would be silently wrong). Negative values pass
// (a strip restart is -1; a face's range is checked when it is built).
bool integral_index(double v, int64_t& out) {
  if (!(std::abs(v) <= static_cast<double>(std::numeric_limits<int>::max())) || v != std::floor(v)) return false;
  out = static_cast<int64_t>(v);
  return true;
}

// ---------------------------------------------------------------------------------------------
// Writing

void append_double(std::string& s, double v) {
  char buf[32];
  auto [p, ec] = std::to_chars(buf, buf + sizeof(buf), v);  // shortest text that reads back exactly
  s.append(buf, p);
}

void append_int(std::string& s, int64_t v) {
  char buf[24];
  auto [p, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  s.append(buf, p);
}

void write_bytes_atomic(const fs::path& path, const std::string& bytes) { write_file_atomic(path, bytes); }

// Writers refuse what the readers refuse: a file geotex cannot read back is never written.
void require_finite_points(const Mesh& mesh, const fs::path& path) {
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
      throw InvalidInput(fmt::format("{}: not written: vertex {} has a non-finite coordinate ({}, {}, {})",
                                     path.string(), v.idx(), p[0], p[1], p[2]));
  }
}

void require_finite_values(const double* v, size_t n, const std::string& what, const fs::path& path) {
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i]))
      throw InvalidInput(fmt::format("{}: not written: {} {} is {}", path.string(), what, i, v[i]));
}
}  // namespace detail

using namespace detail;

namespace {


// Triangulate (fans), validate and build the halfedge mesh.
Mesh build_from_soup(const fs::path& path, const Soup& soup, const ReadOptions& opt,
                     ReadReport& rep) {
  const size_t nv = soup.n_vertices();
  if (nv == 0) throw InvalidInput(fmt::format("{}: the file holds no vertices", path.string()));
  if (nv > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw InvalidInput(fmt::format("{}: {} vertices; geotex meshes hold at most 2^31 - 1", path.string(), nv));
  MatrixX3d V(nv, 3);
  for (size_t i = 0; i < nv; ++i) {
    V(i, 0) = soup.xyz[3 * i];
    V(i, 1) = soup.xyz[3 * i + 1];
    V(i, 2) = soup.xyz[3 * i + 2];
    if (!V.row(i).allFinite())
      throw InvalidInput(fmt::format("{}: vertex {} has a non-finite coordinate ({}, {}, {})",
                                     path.string(), i, V(i, 0), V(i, 1), V(i, 2)));
  }
  size_t n_tris = 0;
  for (size_t p = 0; p < soup.n_polygons(); ++p) {
    const int64_t n = soup.poly_offsets[p + 1] - soup.poly_offsets[p];
    if (n < 3)
      throw IoError(fmt::format("{}: face {} has {} corner(s); a face needs at least 3",
                                path.string(), p, n));
    if (n > 3) ++rep.triangulated_polygons;
    n_tris += static_cast<size_t>(n - 2);
  }
  if (n_tris == 0) throw InvalidInput(fmt::format("{}: the file holds no faces", path.string()));
  MatrixX3i F(n_tris, 3);
  size_t t = 0;
  for (size_t p = 0; p < soup.n_polygons(); ++p) {
    const int64_t* idx = soup.poly_items.data() + soup.poly_offsets[p];
    const int64_t n = soup.poly_offsets[p + 1] - soup.poly_offsets[p];
    for (int64_t k = 0; k < n; ++k)
      if (idx[k] < 0 || idx[k] >= static_cast<int64_t>(nv))
        throw InvalidInput(fmt::format("{}: face {} refers to vertex {}, but there are {} vertices",
                                       path.string(), p, idx[k], nv));
    for (int64_t k = 1; k + 1 < n; ++k) {
      F(t, 0) = static_cast<int>(idx[0]);
      F(t, 1) = static_cast<int>(idx[k]);
      F(t, 2) = static_cast<int>(idx[k + 1]);
      ++t;
    }
  }
  BuildOptions build_options;
  build_options.fix_orientation = opt.repair;
  build_options.split_nonmanifold_vertices = opt.repair;
  Mesh mesh = make_mesh(V, F, &rep.build, build_options);
  const BuildReport& b = rep.build;
  if (b.degenerate_faces)
    rep.warnings.push_back(fmt::format("dropped {} degenerate face(s) (a vertex used twice)", b.degenerate_faces));
  if (b.duplicate_faces)
    rep.warnings.push_back(fmt::format("dropped {} duplicate face(s)", b.duplicate_faces));
  if (b.nonmanifold_faces)
    rep.warnings.push_back(fmt::format(
        "dropped {} non-manifold face(s) (an edge with more than two faces, or a vertex joining separate fans)",
        b.nonmanifold_faces));
  if (b.flipped_faces)
    rep.warnings.push_back(fmt::format("turned {} face(s) round to agree with their neighbours' orientation",
                                       b.flipped_faces));
  if (b.split_vertices)
    rep.warnings.push_back(fmt::format(
        "split {} non-manifold vertex(es) (several fans meeting at a point) into {} extra vertex(es), "
        "appended after the file's vertices", b.split_vertices, b.added_vertices));
  if (b.nonmanifold_vertices)
    rep.warnings.push_back(fmt::format("{} vertex(es) join several fans (non-manifold, kept)", b.nonmanifold_vertices));
  if (b.isolated_vertices)
    rep.warnings.push_back(fmt::format("{} vertex(es) belong to no face (kept)", b.isolated_vertices));
  if (opt.strict && b.dropped() + b.repaired() + b.nonmanifold_vertices > 0)
    throw InvalidInput(fmt::format("{}: the mesh would be changed to read it (strict mode): {}", path.string(),
                                   fmt::join(rep.warnings, "; ")));
  if (mesh.n_faces() == 0)
    throw InvalidInput(fmt::format("{}: no usable face is left after dropping {} face(s)",
                                   path.string(), b.dropped()));
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// OBJ

Soup parse_obj(const fs::path& path, std::string_view data, ReadReport& rep) {
  Soup soup;
  LineReader lr{without_bom(data)};
  std::string_view line;
  std::vector<int64_t> poly;
  size_t unknown = 0;
  while (lr.next(line)) {
    std::string_view rest = line;
    const std::string_view key = next_token(rest);
    if (key.empty() || key.front() == '#') continue;
    if (key == "v") {
      double c[3];
      for (int k = 0; k < 3; ++k) {
        const auto tok = next_token(rest);
        if (tok.empty()) malformed(path, lr.line_no, fmt::format("vertex with {} coordinate(s); expected 3 (truncated file?)", k));
        if (!parse_double(tok, c[k])) malformed(path, lr.line_no, fmt::format("'{}' is not a number", tok));
      }
      soup.xyz.insert(soup.xyz.end(), c, c + 3);
    } else if (key == "f") {
      poly.clear();
      for (auto tok = next_token(rest); !tok.empty(); tok = next_token(rest)) {
        const auto slash = tok.find('/');
        int64_t idx;
        if (!parse_int64(tok.substr(0, slash), idx) || idx == 0)
          malformed(path, lr.line_no, fmt::format("'{}' is not a vertex reference", tok));
        // OBJ indices are 1-based; negative ones count back from the latest vertex.
        poly.push_back(idx > 0 ? idx - 1 : static_cast<int64_t>(soup.n_vertices()) + idx);
      }
      if (poly.size() < 3)
        malformed(path, lr.line_no, fmt::format("face with {} vertex reference(s); expected at least 3 (truncated file?)", poly.size()));
      soup.add_polygon(poly.data(), poly.size());
    } else if (key == "vn" || key == "vt" || key == "vp" || key == "o" || key == "g" || key == "s" ||
               key == "usemtl" || key == "mtllib" || key == "l" || key == "p") {
      continue;
    } else {
      ++unknown;
    }
  }
  if (unknown) rep.warnings.push_back(fmt::format("ignored {} line(s) with unknown keywords", unknown));
  rep.format = "obj";
  return soup;
}

// ---------------------------------------------------------------------------------------------
// OFF

Soup parse_off(const fs::path& path, std::string_view data, ReadReport& rep) {
  Soup soup;
  LineReader lr{without_bom(data)};
  std::string_view line;
  // Skip comments and blank lines.
  auto next_content = [&](std::string_view& l) {
    while (lr.next(l)) {
      const auto hash = l.find('#');
      if (hash != std::string_view::npos) l = l.substr(0, hash);
      std::string_view probe = l;
      if (!next_token(probe).empty()) return true;
    }
    return false;
  };
  if (!next_content(line)) throw IoError(fmt::format("{}: empty OFF file", path.string()));
  std::string_view rest = line;
  std::string head(next_token(rest));
  if (head.size() < 3 || head.substr(head.size() - 3) != "OFF")
    throw IoError(fmt::format("{}: not an OFF file (first word '{}')", path.string(), head));
  if (head.find("4") != std::string::npos || head.find("n") != std::string::npos)
    throw IoError(fmt::format("{}: OFF variant '{}' is not supported", path.string(), head));
  std::string_view counts = rest;
  if (next_token(rest).empty()) {  // counts on the next line
    if (!next_content(line)) throw IoError(fmt::format("{}: OFF header without counts", path.string()));
    counts = line;
  }
  if (counts.find("BINARY") != std::string_view::npos)
    throw IoError(fmt::format("{}: binary OFF is not supported", path.string()));
  int64_t nv = -1, nf = -1;
  if (!parse_int64(next_token(counts), nv) || !parse_int64(next_token(counts), nf) || nv < 0 || nf < 0)
    malformed(path, lr.line_no, "expected the vertex and face counts");
  if (nv > (1ll << 31) || nf > (1ll << 31)) malformed(path, lr.line_no, "counts too large");
  // Every vertex takes at least 6 bytes ("0 0 0\n") and every face 8: a larger count cannot fit.
  if (static_cast<uint64_t>(nv) * 6 + static_cast<uint64_t>(nf) * 8 > data.size() + 16)
    throw IoError(fmt::format("{}: truncated: the header declares {} vertices and {} faces, more than the file can hold",
                              path.string(), nv, nf));
  require_memory(fmt::format("{}: reading {} faces and {} vertices", path.string(), nf, nv), mesh_read_bytes(nf, nv));
  rep.file_vertices = nv;
  soup.xyz.reserve(3 * nv);
  for (int64_t i = 0; i < nv; ++i) {
    if (!next_content(line))
      throw IoError(fmt::format("{}: truncated: the header declares {} vertices, the file has {}",
                                path.string(), nv, i));
    rest = line;
    for (int k = 0; k < 3; ++k) {
      double c;
      const auto tok = next_token(rest);
      if (!parse_double(tok, c)) malformed(path, lr.line_no, fmt::format("bad vertex coordinate '{}'", tok));
      soup.xyz.push_back(c);
    }
  }
  std::vector<int64_t> poly;
  for (int64_t f = 0; f < nf; ++f) {
    if (!next_content(line))
      throw IoError(fmt::format("{}: truncated: the header declares {} faces, the file has {}",
                                path.string(), nf, f));
    rest = line;
    int64_t n;
    if (!parse_int64(next_token(rest), n) || n < 0 || n > 1000000)
      malformed(path, lr.line_no, "expected the number of corners of a face");
    poly.resize(n);
    for (int64_t k = 0; k < n; ++k)
      if (!parse_int64(next_token(rest), poly[k]))
        malformed(path, lr.line_no, fmt::format("face lists {} corners but has fewer indices", n));
    soup.add_polygon(poly.data(), poly.size());
  }
  rep.format = "off";
  return soup;
}

// ---------------------------------------------------------------------------------------------
// STL

Soup stl_from_corners(const std::vector<float>& corners, ReadReport& rep) {
  // STL repeats every corner; merge exactly equal coordinates into one vertex.
  Soup soup;
  struct Key {
    float x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint32_t a, b, c;
      std::memcpy(&a, &k.x, 4);
      std::memcpy(&b, &k.y, 4);
      std::memcpy(&c, &k.z, 4);
      uint64_t h = a * 0x9E3779B97F4A7C15ull;
      h ^= b + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      h ^= c + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      return h;
    }
  };
  std::unordered_map<Key, int64_t, KeyHash> index;
  const size_t n_corners = corners.size() / 3;
  index.reserve(n_corners);
  std::vector<int64_t> tri(3);
  for (size_t c = 0; c < n_corners; ++c) {
    Key k{corners[3 * c], corners[3 * c + 1], corners[3 * c + 2]};
    auto [it, inserted] = index.emplace(k, static_cast<int64_t>(soup.n_vertices()));
    if (inserted) soup.xyz.insert(soup.xyz.end(), {double(k.x), double(k.y), double(k.z)});
    tri[c % 3] = it->second;
    if (c % 3 == 2) soup.add_polygon(tri.data(), 3);
  }
  rep.merged_vertices = n_corners - soup.n_vertices();
  return soup;
}

Soup parse_stl(const fs::path& path, std::string_view data, ReadReport& rep) {
  // Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. Some binary files start with
  // "solid" too, so the size decides first. Ascii lines may be indented, the first one too.
  const bool starts_solid = detail::starts_ascii_stl(data);
  if (data.size() >= 84) {
    uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    const uint64_t expect = 84ull + 50ull * n;
    const bool looks_ascii = starts_solid && data.find("facet") != std::string_view::npos;
    if (expect == data.size() || !looks_ascii) {
      if (data.size() < expect)
        throw IoError(fmt::format("{}: truncated binary STL: {} triangles declared, room for {}",
                                  path.string(), n, (data.size() - 84) / 50));
      // Vertices are not known before merging: a closed mesh has half as many as triangles.
      require_memory(fmt::format("{}: reading {} faces and about {} vertices", path.string(), n, n / 2),
                     mesh_read_bytes(n, n / 2));
      std::vector<float> corners(9ull * n);
      for (uint32_t t = 0; t < n; ++t)
        std::memcpy(&corners[9ull * t], data.data() + 84 + 50ull * t + 12, 36);
      rep.format = "stl (binary)";
      rep.file_polygons = n;
      return stl_from_corners(corners, rep);
    }
  } else if (!starts_solid) {
    throw IoError(fmt::format("{}: not an STL file (too short for binary, no 'solid' header)", path.string()));
  }
  std::vector<float> corners;
  LineReader lr{without_bom(data)};
  std::string_view line;
  size_t in_facet = 0;
  bool ended = false;
  while (lr.next(line)) {
    std::string_view rest = line;
    const auto key = next_token(rest);
    if (key == "endsolid") ended = true;
    if (key == "vertex") {
      for (int k = 0; k < 3; ++k) {
        double c;
        const auto tok = next_token(rest);
        if (!parse_double(tok, c)) malformed(path, lr.line_no, fmt::format("bad vertex coordinate '{}'", tok));
        // STL holds 32-bit floats; a larger finite number has no float (the cast would be undefined).
        if (std::isfinite(c) && std::abs(c) > std::numeric_limits<float>::max())
          malformed(path, lr.line_no, fmt::format("coordinate {} is beyond the range of STL's 32-bit floats", tok));
        corners.push_back(static_cast<float>(c));
      }
      ++in_facet;
    } else if (key == "endfacet") {
      if (in_facet != 3) malformed(path, lr.line_no, fmt::format("facet with {} vertices; expected 3", in_facet));
      in_facet = 0;
    }
  }
  if (in_facet != 0 || corners.size() % 9 != 0)
    throw IoError(fmt::format("{}: truncated ascii STL (a facet is not closed)", path.string()));
  if (!ended) rep.warnings.push_back("no 'endsolid' line: the file may be truncated");
  rep.format = "stl (ascii)";
  rep.file_polygons = corners.size() / 9;
  return stl_from_corners(corners, rep);
}

std::string obj_text(const Mesh& mesh) {
  std::string s;
  s.reserve(mesh.n_vertices() * 60 + mesh.n_faces() * 30);
  s += "# written by geotex\n";
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    s += "v ";
    append_double(s, p[0]); s += ' ';
    append_double(s, p[1]); s += ' ';
    append_double(s, p[2]); s += '\n';
  }
  for (auto f : mesh.faces()) {
    s += 'f';
    for (auto v : f.vertices()) { s += ' '; append_int(s, v.idx() + 1); }
    s += '\n';
  }
  return s;
}

std::string off_text(const Mesh& mesh) {
  std::string s = fmt::format("OFF\n{} {} 0\n", mesh.n_vertices(), mesh.n_faces());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    append_double(s, p[0]); s += ' ';
    append_double(s, p[1]); s += ' ';
    append_double(s, p[2]); s += '\n';
  }
  for (auto f : mesh.faces()) {
    s += '3';
    for (auto v : f.vertices()) { s += ' '; append_int(s, v.idx()); }
    s += '\n';
  }
  return s;
}

std::string stl_bytes(const Mesh& mesh, bool binary, const fs::path& path) {
  // STL stores 32-bit floats: a larger coordinate would become inf.
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k)
      if (std::abs(mesh.point(v)[k]) > std::numeric_limits<float>::max())
        throw InvalidInput(fmt::format("{}: not written: vertex {} has coordinate {}, beyond STL's 32-bit floats",
                                       path.string(), v.idx(), mesh.point(v)[k]));
  std::string s;
  auto tri = [&](Mesh::FaceHandle f, Vec3 (&c)[3], Vec3& n) {
    int k = 0;
    for (auto v : mesh.fv_range(f)) c[k++] = to_eigen(mesh.point(v));
    n = (c[1] - c[0]).cross(c[2] - c[0]);
    const double len = n.norm();
    if (len > 0) n /= len;
  };
  Vec3 c[3], n;
  if (binary) {
    s.assign(80, '\0');
    const char* head = "geotex binary STL";
    std::memcpy(s.data(), head, std::strlen(head));
    append_bin<uint32_t>(s, static_cast<uint32_t>(mesh.n_faces()));
    for (auto f : mesh.faces()) {
      tri(f, c, n);
      for (int k = 0; k < 3; ++k) append_bin<float>(s, static_cast<float>(n[k]));
      for (auto& p : c)
        for (int k = 0; k < 3; ++k) append_bin<float>(s, static_cast<float>(p[k]));
      append_bin<uint16_t>(s, 0);
    }
  } else {
    s = "solid geotex\n";
    for (auto f : mesh.faces()) {
      tri(f, c, n);
      s += fmt::format("facet normal {} {} {}\nouter loop\n", float(n[0]), float(n[1]), float(n[2]));
      for (auto& p : c) {
        s += "vertex ";
        for (int k = 0; k < 3; ++k) { append_double(s, static_cast<float>(p[k])); s += k < 2 ? ' ' : '\n'; }
      }
      s += "endloop\nendfacet\n";
    }
    s += "endsolid geotex\n";
  }
  return s;
}
}  // namespace

// ---------------------------------------------------------------------------------------------

namespace {
// What a file of mode \p m is, when it is not a regular file.
const char* kind_of_special(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISSOCK(m)) return "a socket";
  if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
  return "not a regular file";
}

[[noreturn]] void refuse_input(const std::string& name, int e) {
  if (e == ENOENT) throw IoError(fmt::format("{}: no such file", name));
  if (e == ELOOP) throw IoError(fmt::format("{}: is a loop of symbolic links (they never reach a file)", name));
  if (e == ENOTDIR) throw IoError(fmt::format("{}: no such file (a part of the path is not a folder)", name));
  throw IoError(fmt::format("{}: cannot read ({})", name, std::strerror(e)));
}

void require_regular(const std::string& name, mode_t m) {
  if (S_ISREG(m)) return;
  if (S_ISDIR(m)) throw IoError(fmt::format("{}: is a directory", name));
  throw IoError(fmt::format("{}: is {}; geotex reads only regular files", name, kind_of_special(m)));
}
}  // namespace

void require_input_file(const fs::path& path, const std::string& what) {
  const std::string name = what.empty() ? path.string() : what + " " + path.string();
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) refuse_input(name, errno);
  require_regular(name, st.st_mode);
}

std::string read_regular_file(const fs::path& path, size_t max_bytes, const std::string& what) {
  const std::string name = path.string();
  const std::string limit_of = what.empty() ? "this input" : what;
  // stat first: opening a FIFO or a tape device can block or have effects.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) refuse_input(name, errno);
  require_regular(name, st.st_mode);
  // O_NONBLOCK: if a FIFO took the file's place since the stat, open and read return at once.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    if (e == ENOENT || e == ELOOP) refuse_input(name, e);
    throw IoError(fmt::format("{}: cannot open for reading ({})", name, std::strerror(e)));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &st) != 0) throw IoError(fmt::format("{}: cannot read ({})", name, std::strerror(errno)));
  require_regular(name, st.st_mode);
  auto too_large = [&]() {
    return IoError(fmt::format("{}: larger than {}, the limit for {}", name, human_bytes(max_bytes), limit_of));
  };
  if (static_cast<uint64_t>(st.st_size) > max_bytes) throw too_large();
  require_memory(fmt::format("{}: reading {} of file", name, format_bytes(static_cast<size_t>(st.st_size))),
                 static_cast<size_t>(st.st_size));
  auto read_some = [&](char* buf, size_t len) -> size_t {
    for (;;) {
      const ssize_t n = ::read(fd, buf, len);
      if (n >= 0) return static_cast<size_t>(n);
      const int e = errno;
      if (e == EINTR) continue;
      if (e == EAGAIN) throw IoError(fmt::format("{}: reading would block; geotex reads only regular files", name));
      if (e == EISDIR) throw IoError(fmt::format("{}: is a directory", name));
      throw IoError(fmt::format("{}: read failed ({})", name, std::strerror(e)));
    }
  };
  // The file as it was when opened: bytes another process appends meanwhile are not read, so a file
  // that keeps growing cannot keep a reader busy (issue 30). Every format geotex reads is complete
  // at the size it had; a writer still busy shows as a truncated file.
  std::string data(static_cast<size_t>(st.st_size), '\0');
  size_t got = 0;
  while (got < data.size()) {
    const size_t n = read_some(data.data() + got, data.size() - got);
    if (n == 0) break;  // the file shrank
    got += n;
  }
  data.resize(got);
  if (st.st_size > 0) return data;
  // No size (/proc and similar, or an empty file being written): read to the end, up to the limit
  // (for meshes, which have none of their own, that of a stream).
  max_bytes = std::min(max_bytes, kMaxStreamBytes);
  std::vector<char> chunk(65536);
  for (size_t n; (n = read_some(chunk.data(), chunk.size())) > 0;) {
    if (data.size() + n > max_bytes) throw too_large();
    data.append(chunk.data(), n);
  }
  return data;
}

MeshFormat format_from_path(const fs::path& path) {
  const fs::path inner = is_gzip_path(path) ? path.stem() : path;
  const std::string ext = lower(inner.extension().string());
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".gltf") return MeshFormat::Gltf;
  if (ext == ".glb") return MeshFormat::Glb;
  throw IoError(fmt::format("{}: unknown mesh format '{}' (use .obj, .ply, .off, .stl, .gltf or .glb, "
                            "optionally gzipped as .ply.gz)", path.string(), ext.empty() ? "no extension" : ext));
}

MeshFormat output_format_from_path(const fs::path& path) {
  if (is_gzip_path(path))
    throw IoError(fmt::format("{}: geotex reads gzipped meshes but does not write them; name the output "
                              "without .gz (and compress it afterwards)", path.string()));
  return format_from_path(path);
}

Mesh read_mesh_from_bytes(std::string_view data, MeshFormat format, const ReadOptions& options,
                          ReadReport* report, const std::string& name) {
  const fs::path path(name);
  if (data.empty()) throw IoError(fmt::format("{}: the file is empty", name));
  ReadReport rep;
  Soup soup;
  switch (format) {
    case MeshFormat::Obj: soup = parse_obj(path, data, rep); break;
    case MeshFormat::Off: soup = parse_off(path, data, rep); break;
    case MeshFormat::Stl: soup = parse_stl(path, data, rep); break;
    case MeshFormat::Ply: soup = soup_from_ply(path, parse_ply(path, data), rep); break;
    case MeshFormat::Gltf:
    case MeshFormat::Glb: {
      detail::GltfSoup g = detail::read_gltf(data, format == MeshFormat::Glb, path);
      soup.xyz = std::move(g.xyz);
      for (size_t t = 0; t + 2 < g.triangles.size(); t += 3) soup.add_polygon(g.triangles.data() + t, 3);
      rep.format = g.format;
      rep.warnings = std::move(g.warnings);
      rep.notes = std::move(g.notes);
      break;
    }
  }
  rep.file_vertices = soup.n_vertices();
  if (rep.file_polygons == 0) rep.file_polygons = soup.n_polygons();
  // Text formats without counts (OBJ) or with numbers that may lose digits at a cut (any text format)
  // cannot always tell a truncated file from a complete one; a missing final newline is the one sign.
  // (ASCII STL has its 'endsolid' for that.) A comment as the last line is no sign.
  const bool text = format == MeshFormat::Obj || format == MeshFormat::Off || rep.format == "ply (ascii)";
  if (text && data.back() != '\n' && data.back() != '\r') {
    const size_t nl = data.find_last_of("\r\n");
    std::string_view last = data.substr(nl == std::string_view::npos ? 0 : nl + 1);
    const std::string_view key = next_token(last);
    if (!key.empty() && key.front() != '#')
      rep.warnings.push_back("the last line has no end-of-line: the file may be truncated");
  }
  require_memory(fmt::format("{}: reading {} faces and {} vertices", name, soup.n_polygons(), soup.n_vertices()),
                 mesh_read_bytes(soup.n_polygons(), soup.n_vertices()));
  Mesh mesh = build_from_soup(path, soup, options, rep);
  if (report) *report = std::move(rep);
  return mesh;
}

namespace {
// A binary STL declares its triangles in its first 84 bytes: a file too large for the memory left is
// refused before its bytes are read (a sparse 3 GB file took 29 s to read under an 8 GB cap). Anything
// else (not a regular file, not binary STL by its size) is left to the reader.
void check_binary_stl_memory(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_size < 84) return;
  std::ifstream in(path, std::ios::binary);
  char head[84];
  if (!in.read(head, 84)) return;
  uint32_t n;
  std::memcpy(&n, head + 80, 4);
  if (84ull + 50ull * n != static_cast<uint64_t>(st.st_size)) return;
  require_memory(fmt::format("{}: reading {} faces and about {} vertices", path.string(), n, n / 2),
                 static_cast<size_t>(st.st_size) + mesh_read_bytes(n, n / 2));
}

bool is_binary_ply(std::string_view data) {
  const size_t header_end = data.find("end_header");
  return without_bom(data).substr(0, 3) == "ply" && header_end != std::string_view::npos &&
         data.substr(0, header_end).find("format binary") != std::string_view::npos;
}

// Whether the start of a stream already holds a whole mesh of a format that declares its size: a PLY's
// elements, an OFF's vertices and faces, a .glb's length. A text line is whole only up to its end
// ("1.5" may be the start of "1.53"). OBJ and STL declare nothing (nor does gzip): they are read to
// the stream's end, up to kMaxStreamBytes.
bool holds_declared_mesh(std::string_view data) {
  if (data.size() >= 12 && data.substr(0, 4) == "glTF") {
    uint32_t length;
    std::memcpy(&length, data.data() + 8, 4);
    return data.size() >= length;
  }
  const bool ply = without_bom(data).substr(0, 3) == "ply";
  const size_t last_line = data.find_last_of('\n');
  if (last_line == std::string_view::npos) return false;
  const std::string_view lines = is_binary_ply(data) ? data : data.substr(0, last_line + 1);
  try {
    if (ply) {
      parse_ply("-", lines);
      return true;
    }
    if (sniff_format(data) != MeshFormat::Off) return false;
    ReadReport rep;
    parse_off("-", lines, rep);
    return true;
  } catch (const Error&) {
    return false;  // not yet (or not readable: the read to the end says why)
  }
}
}  // namespace

Mesh read_mesh(const fs::path& path, const ReadOptions& options, ReadReport* report) {
  if (path == kStdioPath) {
    const detail::StdinBytes in = detail::read_stdin(kMaxStreamBytes, holds_declared_mesh);
    if (in.data.empty()) throw IoError("standard input (-): nothing was read (an empty pipe)");
    std::string_view content = in.data;
    std::string unpacked;
    if (detail::is_gzip_magic(content)) content = unpacked = gunzip(content, "standard input (-)");
    // The part of a line that followed the mesh is not a cut last line of it.
    if (in.stopped_early && !is_binary_ply(content) && content.find_last_of('\n') != std::string_view::npos)
      content = content.substr(0, content.find_last_of('\n') + 1);
    ReadReport rep;
    Mesh mesh = read_mesh_from_bytes(content, sniff_format(content), options, &rep, "-");
    if (in.stopped_early)
      rep.notes.push_back("standard input: read up to the mesh's declared end; what followed was not read");
    if (report) *report = std::move(rep);
    return mesh;
  }
  const MeshFormat format = format_from_path(path);
  if (format == MeshFormat::Stl && !is_gzip_path(path)) check_binary_stl_memory(path);
  const std::string data = read_file_bytes(path);
  if (!is_gzip_path(path)) return read_mesh_from_bytes(data, format, options, report, path.string());
  // The content of a gzip file is limited like a stream's; its name keeps the .gz (messages name the file).
  const std::string content = gunzip(data, path.string());
  return read_mesh_from_bytes(content, format, options, report, path.string());
}

void write_mesh(const Mesh& mesh, const fs::path& path, const WriteOptions& options) {
  const MeshFormat f = path == kStdioPath ? options.format : output_format_from_path(path);
  require_finite_points(mesh, path);
  switch (f) {
    case MeshFormat::Gltf:
    case MeshFormat::Glb: write_bytes_atomic(path, detail::gltf_bytes(mesh, f == MeshFormat::Glb, path)); break;
    case MeshFormat::Obj: write_bytes_atomic(path, obj_text(mesh)); break;
    case MeshFormat::Off: write_bytes_atomic(path, off_text(mesh)); break;
    case MeshFormat::Stl: write_bytes_atomic(path, stl_bytes(mesh, options.binary, path)); break;
    case MeshFormat::Ply: write_bytes_atomic(path, ply_bytes(mesh, {}, options.binary, path)); break;
  }
}

void write_ply(const Mesh& mesh, const fs::path& path, const PlyExtras& extras, bool binary) {
  require_finite_points(mesh, path);
  write_bytes_atomic(path, ply_bytes(mesh, extras, binary, path));
}

void write_text_atomic(const fs::path& path, const std::string& text) { write_bytes_atomic(path, text); }

EdgeValues read_edge_values(const fs::path& path, const std::string& property) {
  const PlyData d = read_ply_data(path);
  const PlyElement* e = d.find("edge");
  if (!e) throw IoError(fmt::format("{}: no 'edge' element", path.string()));
  for (const std::string p : {"vertex1", "vertex2"})
    if (!e->scalars.count(p)) throw IoError(fmt::format("{}: edge element has no '{}'", path.string(), p));
  if (!e->scalars.count(property))
    throw IoError(fmt::format("{}: edge element has no '{}' property", path.string(), property));
  const auto &v1 = e->scalars.at("vertex1"), &v2 = e->scalars.at("vertex2"), &values = e->scalars.at(property);
  if (v1.size() != e->count || v2.size() != e->count || values.size() != e->count)
    throw IoError(fmt::format("{}: edge element declares a property twice", path.string()));
  // Vertex indices are stored as numbers of any PLY type: only non-negative integers that fit an int
  // are indices (a cast of anything else to int is undefined behaviour).
  auto index = [&](double v, size_t row) {
    if (!(v >= 0 && v <= std::numeric_limits<int>::max() && v == std::floor(v)))
      throw IoError(fmt::format("{}: edge {} has vertex index {}, not a non-negative integer", path.string(), row,
                                detail::exact_number(v)));
    return static_cast<int>(v);
  };
  EdgeValues out;
  out.edges.resize(e->count, 2);
  out.values.resize(e->count);
  for (size_t i = 0; i < e->count; ++i) {
    out.edges(i, 0) = index(v1[i], i);
    out.edges(i, 1) = index(v2[i], i);
    if (!std::isfinite(values[i]))
      throw InvalidInput(fmt::format("{}: edge {} has a non-finite '{}' ({})", path.string(), i, property, values[i]));
    out.values[i] = values[i];
  }
  return out;
}

void write_edge_values(const Mesh& mesh, const Eigen::VectorXd& values, const std::string& property,
                       const fs::path& path, bool binary) {
  if (static_cast<size_t>(values.size()) != mesh.n_edges())
    throw InvalidInput(fmt::format("{} edge values for a mesh of {} edges", values.size(), mesh.n_edges()));
  PlyExtras x;
  PlyExtras::Element e{"edge", {}, {}};
  const MatrixX2i E = edges(mesh);
  e.int_props["vertex1"].assign(E.col(0).data(), E.col(0).data() + E.rows());
  e.int_props["vertex2"].assign(E.col(1).data(), E.col(1).data() + E.rows());
  e.double_props[property].assign(values.data(), values.data() + values.size());
  x.elements.push_back(std::move(e));
  write_ply(mesh, path, x, binary);
}

void write_polylines_obj(const MatrixX3d& V, const MatrixX2i& segments, const fs::path& path) {
  // Only the vertices the segments use, renumbered.
  std::vector<int> remap(V.rows(), -1);
  std::string s = "# line segments written by geotex\n";
  int next = 0;
  for (Eigen::Index i = 0; i < segments.rows(); ++i)
    for (int k = 0; k < 2; ++k) {
      const int v = segments(i, k);
      if (v < 0 || v >= V.rows()) throw InvalidInput("write_polylines_obj: segment index out of range");
      if (remap[v] >= 0) continue;
      if (!V.row(v).allFinite())
        throw InvalidInput(fmt::format("{}: not written: vertex {} has a non-finite coordinate ({}, {}, {})",
                                       path.string(), v, V(v, 0), V(v, 1), V(v, 2)));
      remap[v] = next++;
      s += "v ";
      append_double(s, V(v, 0)); s += ' ';
      append_double(s, V(v, 1)); s += ' ';
      append_double(s, V(v, 2)); s += '\n';
    }
  for (Eigen::Index i = 0; i < segments.rows(); ++i)
    s += fmt::format("l {} {}\n", remap[segments(i, 0)] + 1, remap[segments(i, 1)] + 1);
  write_bytes_atomic(path, s);
}

}  // namespace geotex
