#pragma once
//! \file io.h Reading and writing meshes: OBJ, PLY (ascii and binary, faces or triangle strips),
//! OFF, STL (ascii and binary) and glTF 2.0 (.glb, and .gltf with data-URI or external .bin buffers).
//! Inputs may be gzipped (`x.ply.gz`: the inner extension names the format). The path `-` is
//! standard input (the format sniffed from its bytes) or standard output (the format given by
//! WriteOptions::format).
//!
//! Readers parse into a polygon soup, check it (counts against the header, finite coordinates,
//! index ranges), triangulate polygons as fans, and build the halfedge mesh with make_mesh(),
//! which drops and counts degenerate, duplicate and non-manifold faces. Nothing is dropped
//! silently: every count lands in ReadReport, and ReadOptions::strict turns a drop into an error.
//! Text is read with any line end (LF, CRLF, a lone CR) and a leading UTF-8 byte order mark is
//! skipped. Only regular files are read (a FIFO, device or socket is refused at once).
//!
//! Writers refuse what the readers refuse (non-finite coordinates or values: InvalidInput, before
//! any file is touched) and write through write_file_atomic() (output.h): to a temporary beside the
//! target, renamed into place, so a failed write never leaves a partial file and never damages an
//! existing one; inside an OutputTransaction, only when every output of the command is complete.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

enum class MeshFormat { Obj, Ply, Off, Stl, Gltf, Glb };

//! The path that means standard input (read_mesh) or standard output (write_mesh).
inline constexpr const char* kStdioPath = "-";

//! Size limits of the inputs read whole into memory (besides meshes, which have none: their size is
//! their content). A regular file cannot be endless, but one that grows while it is read, or a
//! /proc file, can be: reading stops at the limit with an IoError.
inline constexpr size_t kMaxHandlesFileBytes = size_t(256) << 20;  //!< deformation handles (JSON)
inline constexpr size_t kMaxTextFileBytes = size_t(4) << 30;       //!< feature, field and point text files
//! Meshes that have no size of their own to stop at: standard input, and a gzipped file's content.
inline constexpr size_t kMaxStreamBytes = size_t(4) << 30;

//! Checks that \p path can be opened as an input file, without opening it. The error names the
//! real cause: "no such file", "is a loop of symbolic links", "is a directory", "is a FIFO (named
//! pipe)", "is a device", "is a socket", "cannot read (Permission denied)". \p what prefixes the
//! path in the message (a flag such as "--edges"; "" for none).
//! \throw IoError if \p path is anything but an existing regular file (after following links).
void require_input_file(const std::filesystem::path& path, const std::string& what = "");

//! The bytes of a regular file. A directory, FIFO, socket or device is refused at once (stat before
//! opening; the open is non-blocking, so a FIFO swapped in meanwhile cannot block either).
//! Reading stops at the size the file had when it was opened: a file another process keeps
//! appending to is read as it was then, in bounded time. (A file with no size, as in /proc, is
//! read to its end, up to \p max_bytes.)
//! \p what names the kind of input in the size-limit message ("a handles file").
//! \throw IoError if missing, not a regular file, unreadable, or larger than \p max_bytes.
std::string read_regular_file(const std::filesystem::path& path, size_t max_bytes = SIZE_MAX,
                              const std::string& what = "");

//! The format named by a path's extension (case-insensitive); for `x.ply.gz` the inner one (Ply).
//! \throw IoError if unknown.
MeshFormat format_from_path(const std::filesystem::path& path);
//! The format written to \p path: format_from_path() without `.gz` (geotex does not compress).
//! \throw IoError if unknown or gzipped.
MeshFormat output_format_from_path(const std::filesystem::path& path);
//! Whether \p path ends in `.gz` (case-insensitive).
bool is_gzip_path(const std::filesystem::path& path);
//! The format name as written by `--format` ("ply", "obj", "off", "stl", "gltf", "glb").
std::string format_name(MeshFormat format);
//! The format named \p name (case-insensitive). \throw InvalidInput if unknown.
MeshFormat format_from_name(const std::string& name);
//! The format of mesh bytes from their content: a PLY's `ply` line, an OFF header, `glTF` magic
//! (binary glTF), a JSON object with an "asset" (text glTF), an ascii STL's `solid` with a `facet`,
//! a binary STL's size (84 + 50 x its count), else OBJ. Leading blanks and a UTF-8 byte order mark
//! are skipped. Used for standard input, which has no name.
MeshFormat sniff_format(std::string_view data);

//! The content of gzip (or zlib) bytes, at most \p max_bytes. \p name is used in messages.
//! \throw IoError for corrupt or truncated data, or content larger than \p max_bytes.
std::string gunzip(std::string_view data, const std::string& name, size_t max_bytes = kMaxStreamBytes);

struct ReadOptions {
  bool strict = false;  //!< throw instead of dropping or repairing faces (degenerate, duplicate, non-manifold, flipped)
  //! Turn faces that disagree with their neighbours' orientation round, and split non-manifold
  //! vertices into one copy per fan (BuildOptions), instead of dropping those faces.
  bool repair = true;
};

struct ReadReport {
  std::string format;                //!< "obj", "ply (binary_little_endian)", …
  size_t file_vertices = 0;          //!< vertices in the file
  size_t file_polygons = 0;          //!< faces (or strips) in the file
  size_t triangulated_polygons = 0;  //!< polygons with more than 3 corners split into fans
  size_t strip_triangles = 0;        //!< triangles decoded from PLY triangle strips
  size_t merged_vertices = 0;        //!< STL corners merged into shared vertices
  BuildReport build;                 //!< what make_mesh() dropped
  std::vector<std::string> warnings; //!< one line per thing that was dropped or looks wrong
  std::vector<std::string> notes;    //!< informational lines (e.g. triangle strips decoded)
};

//! Read a mesh file; `-` reads standard input (up to kMaxStreamBytes; the format sniffed), and a
//! `.gz` file is decompressed first (up to kMaxStreamBytes).
//! \throw IoError for a missing/unreadable file or one that is not a regular file, unknown extension,
//!        malformed or truncated content (a PLY property or element declared twice, a non-integer or
//!        out-of-type-range value in an integer field, a non-integer vertex index or list count);
//!        InvalidInput for non-finite coordinates, out-of-range indices, an empty result, or (strict)
//!        any dropped face.
Mesh read_mesh(const std::filesystem::path& path, const ReadOptions& options = {},
               ReadReport* report = nullptr);

//! Read a mesh from bytes in memory (same checks as read_mesh); \p name is used in messages, and
//! its folder is where a .gltf's external buffers are looked for.
Mesh read_mesh_from_bytes(std::string_view data, MeshFormat format, const ReadOptions& options = {},
                          ReadReport* report = nullptr, const std::string& name = "<memory>");

struct WriteOptions {
  bool binary = true;  //!< PLY and STL: binary (default) or ascii. OBJ/OFF are always ascii.
  //! The format when the path is `-` (standard output), where no extension names it.
  MeshFormat format = MeshFormat::Ply;
};

//! Write a mesh, atomically; `-` writes it to standard output in WriteOptions::format (inside an
//! OutputTransaction, at commit()). Coordinates are written in full (shortest round-trip decimal in
//! text formats, float64 in PLY; STL and glTF store float32 by definition). A .gltf holds its buffer
//! as a base64 data URI, so it is one file, written atomically like the others.
//! \throw InvalidInput for a non-finite coordinate (or one beyond float range, for STL); IoError on
//!        failure to write (output.h lists the rules).
void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const WriteOptions& options = {});

// ---------------------------------------------------------------------------------------------
// General PLY access, for files that carry more than a mesh (edge labels, tilt, heights).

//! A list property stored flat: items of row r are items[offsets[r] .. offsets[r+1]).
struct PlyList {
  std::vector<int64_t> offsets{0};
  std::vector<double> items;
  size_t rows() const { return offsets.size() - 1; }
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<std::string> order;                 //!< property names in file order
  std::map<std::string, std::vector<double>> scalars;
  std::map<std::string, PlyList> lists;
  bool has(const std::string& p) const { return scalars.count(p) || lists.count(p); }
};

struct PlyData {
  std::string format;               //!< ascii | binary_little_endian | binary_big_endian
  std::vector<PlyElement> elements; //!< in file order
  const PlyElement* find(const std::string& name) const;
};

//! Parse any PLY file (every element, every property). \throw IoError on malformed/truncated content,
//! an element or property declared twice, or an ascii value outside its declared type.
PlyData read_ply_data(const std::filesystem::path& path);
//! Parse PLY bytes in memory.
PlyData parse_ply_bytes(std::string_view data, const std::string& name = "<memory>");

//! Extra data written beside a mesh in a PLY file.
struct PlyExtras {
  //! per-vertex scalar properties (each of size #V), e.g. "height", "feature"
  std::map<std::string, std::vector<double>> vertex_scalars;
  //! additional elements, e.g. an "edge" element with int "vertex1", "vertex2" and a "tilt" or "label"
  struct Element {
    std::string name;
    std::map<std::string, std::vector<int>> int_props;        //!< written as int
    std::map<std::string, std::vector<double>> double_props;  //!< written as double
  };
  std::vector<Element> elements;
};

//! Write a mesh and extra per-vertex properties and elements as PLY, atomically.
//! \throw InvalidInput for a non-finite coordinate or double value.
void write_ply(const Mesh& mesh, const std::filesystem::path& path, const PlyExtras& extras,
               bool binary = true);

//! Per-edge values read from, or written to, a PLY "edge" element (vertex1, vertex2, value).
struct EdgeValues {
  MatrixX2i edges;        //!< #E by 2 vertex indices
  Eigen::VectorXd values; //!< #E values of the named property
};

//! Read the "edge" element of a PLY file and its property \p property ("label", "tilt", …).
//! \throw IoError if the file has no such element or property, or a vertex index is not an integer;
//!        InvalidInput for a non-finite value.
EdgeValues read_edge_values(const std::filesystem::path& path, const std::string& property);

//! Write a mesh with per-edge values (one per mesh edge, OpenMesh edge order) as PLY, atomically.
void write_edge_values(const Mesh& mesh, const Eigen::VectorXd& values, const std::string& property,
                       const std::filesystem::path& path, bool binary = true);

//! Write line segments (e.g. labelled sharp edges) as an OBJ of `v` and `l` lines, atomically.
void write_polylines_obj(const MatrixX3d& V, const MatrixX2i& segments, const std::filesystem::path& path);

//! Write a text file atomically (write_file_atomic() of output.h). \throw IoError on failure.
void write_text_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace geotex
