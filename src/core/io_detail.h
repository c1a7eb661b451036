#pragma once
// Pieces of the mesh readers and writers shared between the io_*.cpp topic files (not public API).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

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

}  // namespace geotex::detail
