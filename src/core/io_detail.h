#pragma once
// Pieces of the mesh readers and writers shared between the io_*.cpp topic files (not public API).

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "geotex/core/io.h"
#include "geotex/core/mesh.h"

namespace geotex::detail {

// Whether \p data starts like an ascii STL: "solid" after an optional UTF-8 byte order mark and blanks.
bool starts_ascii_stl(std::string_view data);

// Whether \p data starts with the gzip magic bytes 1f 8b.
bool is_gzip_magic(std::string_view data);

// Standard input as read by read_stdin(): its bytes, and whether reading stopped before the stream's end.
struct StdinBytes {
  std::string data;
  bool stopped_early = false;  // \p complete said the bytes hold a whole mesh while the stream went on
};
// Standard input, at most \p max_bytes: a regular file (`< FILE`) as large as it was when reading began;
// a pipe to its end, or until \p complete(bytes so far) says they hold a whole mesh (asked as the bytes
// double, and whenever the writer pauses): a writer that never stops cannot keep the reader busy.
// A cancellation point while it waits. \throw IoError beyond \p max_bytes or on a read error.
StdinBytes read_stdin(size_t max_bytes, const std::function<bool(std::string_view)>& complete = {});

// The triangles of a glTF asset as a soup: #V*3 positions (scene coordinates) and #T*3 indices.
struct GltfSoup {
  std::vector<double> xyz;
  std::vector<int64_t> triangles;
  std::string format;  // "gltf (.glb)" or "gltf (.gltf)"
  std::vector<std::string> warnings, notes;
};
// \p binary: .glb bytes, else .gltf JSON (external buffers are read from \p name's folder).
GltfSoup read_gltf(std::string_view data, bool binary, const std::filesystem::path& name);
// A glTF 2.0 asset of one mesh: float positions, uint32 indices. \p binary: .glb, else .gltf with
// the buffer embedded as a data URI. \throw InvalidInput for a coordinate beyond float range.
std::string gltf_bytes(const Mesh& mesh, bool binary, const std::filesystem::path& path);

// ---------------------------------------------------------------------------------------------
// Scanning and writing helpers (io.cpp), shared by the format files.

std::string lower(std::string s);
std::string read_file_bytes(const std::filesystem::path& path);
std::string human_bytes(uint64_t n);
// \p data without a leading UTF-8 byte order mark.
std::string_view without_bom(std::string_view data);

// Lines end with LF, CRLF or a lone CR (classic Mac OS); the line excludes its end.
struct LineReader {
  std::string_view data;
  size_t pos = 0;
  size_t line_no = 0;
  bool next(std::string_view& line) {
    if (pos >= data.size()) return false;
    const size_t end = data.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) {
      line = data.substr(pos);
      pos = data.size();
    } else {
      line = data.substr(pos, end - pos);
      pos = end + 1;
      if (data[end] == '\r' && pos < data.size() && data[pos] == '\n') ++pos;
    }
    ++line_no;
    return true;
  }
};

bool is_space(char c);
// Split off the next whitespace-separated token; empty when none is left.
std::string_view next_token(std::string_view& s);
bool parse_double(std::string_view tok, double& out);
bool parse_int64(std::string_view tok, int64_t& out);
[[noreturn]] void malformed(const std::filesystem::path& path, size_t line, const std::string& what);
// A vertex index stored as a number of any type: an integer within int range.
bool integral_index(double v, int64_t& out);

// A polygon soup before triangulation.
struct Soup {
  std::vector<double> xyz;             // 3 per vertex
  std::vector<int64_t> poly_offsets{0};
  std::vector<int64_t> poly_items;
  size_t n_vertices() const { return xyz.size() / 3; }
  size_t n_polygons() const { return poly_offsets.size() - 1; }
  void add_polygon(const int64_t* idx, size_t n) {
    poly_items.insert(poly_items.end(), idx, idx + n);
    poly_offsets.push_back(static_cast<int64_t>(poly_items.size()));
  }
};

void append_double(std::string& s, double v);
void append_int(std::string& s, int64_t v);
template <class T>
void append_bin(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}
void write_bytes_atomic(const std::filesystem::path& path, const std::string& bytes);
// Writers refuse what the readers refuse: a file geotex cannot read back is never written.
void require_finite_points(const Mesh& mesh, const std::filesystem::path& path);
void require_finite_values(const double* v, size_t n, const std::string& what, const std::filesystem::path& path);

// ---------------------------------------------------------------------------------------------
// PLY (io_ply.cpp)

PlyData parse_ply(const std::filesystem::path& path, std::string_view data);
Soup soup_from_ply(const std::filesystem::path& path, const PlyData& ply, ReadReport& rep);
std::string ply_bytes(const Mesh& mesh, const PlyExtras& extras, bool binary, const std::filesystem::path& path);

}  // namespace geotex::detail
