// Encodings and file kinds every reader must take or refuse clearly (issue 14, class 5 and 7):
// a UTF-8 byte order mark, CRLF and lone-CR line ends, PLY properties declared twice or missing,
// non-integer indices and list counts, and inputs that are not regular files.

#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/feature_file.h"
#include "geotex/texture/texture.h"
#include "geotex/tools/shapes.h"
#include "geotex/tools/viewer.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::read_file;
using geotex::test::TempDir;
using geotex::test::write_file;
namespace fs = std::filesystem;

namespace {

const std::string kBom = "\xEF\xBB\xBF";

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  std::string out;
  size_t pos = 0;
  for (size_t hit; (hit = s.find(from, pos)) != std::string::npos; pos = hit + from.size()) out += s.substr(pos, hit - pos) + to;
  return out + s.substr(pos);
}

template <class E, class F>
::testing::AssertionResult throws_with(F&& f, const std::string& needle) {
  try {
    f();
  } catch (const E& e) {
    if (std::string(e.what()).find(needle) == std::string::npos)
      return ::testing::AssertionFailure() << "message without '" << needle << "': " << e.what();
    return ::testing::AssertionSuccess();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "other exception: " << e.what();
  }
  return ::testing::AssertionFailure() << "no exception";
}

// The bytes of a file geotex writes, in \p name's format.
std::string written(const Mesh& m, const std::string& name, bool binary) {
  TempDir tmp;
  WriteOptions w;
  w.binary = binary;
  write_mesh(m, tmp / name, w);
  return read_file(tmp / name);
}

// Runs \p f in a child process under a time and memory limit; the child's exit code (0: \p f
// returned true), or -1 if it was killed (hung or ran out of memory).
int in_child(const std::function<bool()>& f, unsigned seconds = 10) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::alarm(seconds);
    rlimit lim{size_t(2) << 30, size_t(2) << 30};
    if (!test::kAddressSanitizer) ::setrlimit(RLIMIT_AS, &lim);
    bool ok = false;
    try {
      ok = f();
    } catch (...) {
    }
    ::_exit(ok ? 0 : 1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// True if \p f throws an IoError whose message contains \p needle.
bool io_error_with(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
  } catch (const IoError& e) {
    return std::string(e.what()).find(needle) != std::string::npos;
  } catch (...) {
  }
  return false;
}

}  // namespace

TEST(ReaderQuirks, ByteOrderMarkAndEveryLineEndReadTheSameMesh) {
  const Mesh m = icosphere(1);
  struct Case {
    const char* name;
    bool binary;
  };
  for (const Case c : {Case{"a.obj", false}, Case{"a.off", false}, Case{"a.ply", false}, Case{"a.stl", false}}) {
    const std::string lf = written(m, c.name, c.binary);
    ReadReport ref_rep;
    const Mesh ref = read_mesh_from_bytes(lf, format_from_path(c.name), {}, &ref_rep);
    for (const char* eol : {"\n", "\r\n", "\r"})
      for (bool bom : {false, true}) {
        SCOPED_TRACE(std::string(c.name) + (bom ? " with BOM" : "") + " eol " + (eol[0] == '\n' ? "LF" : eol[1] ? "CRLF" : "CR"));
        const std::string bytes = (bom ? kBom : "") + replace_all(lf, "\n", eol);
        ReadReport rep;
        Mesh r;
        ASSERT_NO_THROW(r = read_mesh_from_bytes(bytes, format_from_path(c.name), {}, &rep));
        ASSERT_EQ(r.n_vertices(), ref.n_vertices());
        EXPECT_TRUE(positions(r) == positions(ref));
        EXPECT_TRUE(faces(r) == faces(ref));
        EXPECT_EQ(rep.warnings, ref_rep.warnings);
      }
  }
  // A binary PLY's header with a BOM or CRLF ends; the body is untouched.
  const std::string bin = written(m, "b.ply", true);
  const size_t body = bin.find("end_header\n") + 11;
  const std::string crlf = replace_all(bin.substr(0, body), "\n", "\r\n") + bin.substr(body);
  for (const std::string& bytes : {kBom + bin, crlf, kBom + crlf})
    EXPECT_TRUE(positions(read_mesh_from_bytes(bytes, MeshFormat::Ply)) == positions(m));
}

TEST(ReaderQuirks, ObjWithBomKeepsItsFirstVertexAndLoneCrDoesNotSwallowLines) {
  // The two examples of issue 14: on main the BOM hid the first 'v' line and a lone CR merged lines.
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  ReadOptions strict;
  strict.strict = true;
  const Mesh a = read_mesh_from_bytes(kBom + obj, MeshFormat::Obj, strict);
  EXPECT_EQ(a.n_vertices(), 4u);
  EXPECT_EQ(a.n_faces(), 4u);
  const Mesh b = read_mesh_from_bytes(replace_all(obj, "\n", "\r"), MeshFormat::Obj, strict);
  EXPECT_EQ(b.n_vertices(), 4u);
  EXPECT_EQ(b.n_faces(), 4u);
}

TEST(ReaderQuirks, BinaryPlyWithLoneCrHeaderKeepsABodyStartingWithLineFeed) {
  // The first body byte is 0x0A: after "end_header\r" it belongs to the body, not to a CRLF.
  const Mesh m = icosphere(0);
  MatrixX3d V = positions(m);
  uint64_t bits = std::bit_cast<uint64_t>(V(0, 0));
  bits = (bits & ~0xFFull) | 0x0A;
  V(0, 0) = std::bit_cast<double>(bits);
  Mesh m2 = m;
  set_positions(m2, V);
  ASSERT_EQ(std::endian::native, std::endian::little);
  const std::string bin = written(m2, "b.ply", true);
  const size_t body = bin.find("end_header\n") + 11;
  ASSERT_EQ(bin[body], '\n');
  const std::string cr = replace_all(bin.substr(0, body), "\n", "\r") + bin.substr(body);
  const Mesh r = read_mesh_from_bytes(cr, MeshFormat::Ply);
  EXPECT_TRUE(positions(r) == V);
  const std::string crlf = replace_all(bin.substr(0, body), "\n", "\r\n") + bin.substr(body);
  EXPECT_TRUE(positions(read_mesh_from_bytes(crlf, MeshFormat::Ply)) == V);
}

TEST(ReaderQuirks, UserTextFilesTakeBomAndEveryLineEnd) {
  TempDir tmp;
  const Mesh cube = make_shape("cube", 0).textured;
  const size_t n = cube.n_vertices();
  std::string weights = "# weights\n";
  for (size_t i = 0; i < n; ++i) weights += (i % 5 == 0) ? "1\n" : "0.25\n";
  const Eigen::VectorXd ref = parse_feature_weights(weights, n);
  for (const char* eol : {"\r\n", "\r"}) {
    const std::string text = kBom + replace_all(weights, "\n", eol);
    EXPECT_TRUE(parse_feature_weights(text, n) == ref);
    write_file(tmp / "w.txt", text);
    EXPECT_TRUE(read_feature_file(tmp / "w.txt", cube) == ref);
  }
  const std::string xyz = "0 0 0\n1 0 0\n# c\n0 1 0\n";
  for (const char* eol : {"\r\n", "\r"}) {
    const MatrixX3d P = parse_point_text(kBom + replace_all(xyz, "\n", eol), false);
    ASSERT_EQ(P.rows(), 3);
    EXPECT_EQ(P(2, 1), 1.0);
    const MatrixX3d Q = parse_point_text(kBom + replace_all("v 0 0 0\nv 1 0 0\nvn 0 0 1\n", "\n", eol), true);
    EXPECT_EQ(Q.rows(), 2);
  }
  const std::string handles = kBom + "{\"handles\":\r\n [{\"vertices\": [0, 1]}]}\r";
  EXPECT_EQ(parse_handles(handles, positions(cube), 1.0).ids.size(), 2u);
  std::string field = kBom;
  for (size_t i = 0; i < n; ++i) field += std::to_string(i) + ((i % 3 == 2) ? "\r" : ", ");
  write_file(tmp / "f.txt", field);
  const Eigen::VectorXd f = read_field_file(tmp / "f.txt", n);
  EXPECT_EQ(f[n - 1], double(n - 1));
}

TEST(ReaderQuirks, PlyPropertiesDeclaredTwiceOrMissingAreRefused) {
  const std::string head = "ply\nformat ascii 1.0\n";
  const std::string face = "element face 1\nproperty list uchar int vertex_indices\n";
  // x twice: on main the six values interleaved (x of vertex 1 was vertex 0's second x).
  const std::string twice = head + "element vertex 3\nproperty float x\nproperty float x\nproperty float y\nproperty float z\n" +
                            face + "end_header\n0 9 0 0\n1 9 0 0\n0 9 1 0\n3 0 1 2\n";
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(twice, MeshFormat::Ply); }, "'x' of element 'vertex' is declared twice"));
  EXPECT_TRUE(throws_with<IoError>([&] { parse_ply_bytes(twice); }, "declared twice"));
  const std::string elem_twice = head + "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n" +
                                 "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n" + face +
                                 "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(elem_twice, MeshFormat::Ply); }, "element 'vertex' is declared twice"));
  const std::string no_z = head + "element vertex 3\nproperty float x\nproperty float y\n" + face +
                           "end_header\n0 0\n1 0\n0 1\n3 0 1 2\n";
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(no_z, MeshFormat::Ply); }, "no 'z'"));
  const std::string no_indices = head + "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n" +
                                 "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(no_indices, MeshFormat::Ply); }, "vertex_indices"));
  const std::string scalar_indices = head + "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n" +
                                     "element face 1\nproperty int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2\n";
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(scalar_indices, MeshFormat::Ply); }, "vertex_indices"));
}

namespace {

std::string ascii_ply(const std::string& index_decl, const std::string& face_row) {
  return "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
         "element face 1\n" + index_decl + "\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + face_row + "\n";
}

// A binary little-endian PLY of a tetrahedron's 4 vertices and one face, with the index list's types
// and bytes given.
std::string binary_ply(const std::string& index_decl, const std::string& face_bytes) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                  "property double z\nelement face 1\n" + index_decl + "\nend_header\n";
  const double V[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  s.append(reinterpret_cast<const char*>(V), sizeof(V));
  return s + face_bytes;
}

template <class T>
std::string bytes_of(std::initializer_list<T> values) {
  std::string s;
  for (T v : values) s.append(reinterpret_cast<const char*>(&v), sizeof(T));
  return s;
}

}  // namespace

TEST(ReaderQuirks, NonIntegerIndicesAndCountsAreRefusedNotTruncated) {
  // Control: well-formed files read.
  EXPECT_EQ(read_mesh_from_bytes(ascii_ply("property list uchar int vertex_indices", "3 0 1 2"), MeshFormat::Ply).n_faces(), 1u);
  EXPECT_EQ(read_mesh_from_bytes(ascii_ply("property list uchar float vertex_indices", "3 0 1 2.0"), MeshFormat::Ply).n_faces(), 1u);
  EXPECT_EQ(read_mesh_from_bytes(binary_ply("property list float double vertex_indices",
                                            bytes_of<float>({3.0f}) + bytes_of<double>({0, 1, 2})), MeshFormat::Ply).n_faces(), 1u);
  // An int field holding 1.5 (main read it as 1).
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(ascii_ply("property list uchar int vertex_indices", "3 0 1.5 2"), MeshFormat::Ply); },
                                   "'1.5' is not an integer"));
  // A uchar count of 300 and a fractional count.
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(ascii_ply("property list uchar int vertex_indices", "300 0 1 2"), MeshFormat::Ply); },
                                   "bad list length '300'"));
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(ascii_ply("property list uchar int vertex_indices", "2.5 0 1 2"), MeshFormat::Ply); },
                                   "bad list length"));
  // A float-typed count in ascii: 2.5, and 9223372036854775808 (found by fuzz/PlyData: an undefined cast).
  for (const char* count : {"2.5", "9223372036854775808", "1e300", "nan", "-1"})
    EXPECT_TRUE(throws_with<IoError>(
        [&] { read_mesh_from_bytes(ascii_ply("property list double int vertex_indices", std::string(count) + " 0 1 2"), MeshFormat::Ply); },
        "bad list length"))
        << count;
  EXPECT_EQ(read_mesh_from_bytes(ascii_ply("property list double int vertex_indices", "3.0 0 1 2"), MeshFormat::Ply).n_faces(), 1u);
  EXPECT_TRUE(throws_with<IoError>(
      [&] {
        read_mesh_from_bytes(binary_ply("property list float int vertex_indices", bytes_of<float>({3.5f}) + bytes_of<int32_t>({0, 1, 2})),
                             MeshFormat::Ply);
      },
      "bad list length 3.5"));
  // A float-typed index of 2.5, 1e300, NaN, or beyond int range: no truncation, no undefined cast.
  for (const char* bad : {"2.5", "1e300", "nan", "3e9", "-3e9", "inf"}) {
    SCOPED_TRACE(bad);
    EXPECT_TRUE(throws_with<IoError>(
        [&] { read_mesh_from_bytes(ascii_ply("property list uchar double vertex_indices", std::string("3 0 1 ") + bad), MeshFormat::Ply); },
        "not an integer index"));
  }
  for (double bad : {2.5, 1e300, std::nan(""), 3e9}) {
    EXPECT_TRUE(throws_with<IoError>(
        [&] {
          read_mesh_from_bytes(binary_ply("property list uchar double vertex_indices", bytes_of<uint8_t>({3}) + bytes_of<double>({0, 1, bad})),
                               MeshFormat::Ply);
        },
        "not an integer index"))
        << bad;
  }
  // Triangle strips likewise.
  const std::string strips = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                             "element tristrips 1\nproperty list int double vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                             "4 0 1 2 1e300\n";
  EXPECT_TRUE(throws_with<IoError>([&] { read_mesh_from_bytes(strips, MeshFormat::Ply); }, "not an integer index"));
  // Any other integer field: an edge's vertex1 of 1.5 in an int property, a uchar label of 256.
  const std::string edges = "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\nelement edge 1\nproperty int vertex1\n"
                            "property int vertex2\nproperty uchar label\nend_header\n";
  EXPECT_TRUE(throws_with<IoError>([&] { parse_ply_bytes(edges + "1.5 2 1\n"); }, "not an integer"));
  EXPECT_TRUE(throws_with<IoError>([&] { parse_ply_bytes(edges + "1 2 256\n"); }, "not an integer in [0, 255]"));
  EXPECT_EQ(parse_ply_bytes(edges + "1 2 255\n").find("edge")->scalars.at("label")[0], 255.0);
}

TEST(ReaderQuirks, HugeOrFractionalIndicesInEveryTextFormat) {
  EXPECT_THROW(read_mesh_from_bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1.5\n", MeshFormat::Obj), IoError);
  EXPECT_THROW(read_mesh_from_bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", MeshFormat::Obj), IoError);
  EXPECT_THROW(read_mesh_from_bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967299\n", MeshFormat::Obj), InvalidInput);
  EXPECT_THROW(read_mesh_from_bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775807\n", MeshFormat::Obj), InvalidInput);
  EXPECT_THROW(read_mesh_from_bytes("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", MeshFormat::Off), IoError);
  EXPECT_THROW(read_mesh_from_bytes("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 4294967298\n", MeshFormat::Off), InvalidInput);
  EXPECT_THROW(read_mesh_from_bytes("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2.5 0 1 2\n", MeshFormat::Off), IoError);
  // ASCII STL holds 32-bit floats: a larger coordinate cannot be one.
  EXPECT_THROW(read_mesh_from_bytes("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e300 0 0\nvertex 0 1 0\n"
                                    "endloop\nendfacet\nendsolid s\n", MeshFormat::Stl), IoError);
}

TEST(ReaderQuirks, SpecialFilesAreRefusedAtOnce) {
  // Each check runs in a child under a 10 s alarm and a 2 GiB memory limit: on main a FIFO blocked
  // forever and /dev/zero was read until memory ran out.
  TempDir tmp;
  const Mesh cube = make_shape("cube", 0).textured;
  const MatrixX3d X = positions(cube);
  for (const char* name : {"fifo.obj", "fifo.ply", "fifo.txt", "fifo.json", "fifo.xyz"})
    ASSERT_EQ(::mkfifo((tmp / name).c_str(), 0644), 0);
  for (const char* name : {"zero.obj", "zero.ply", "zero.txt", "zero.json", "zero.xyz", "zero.stl"})
    fs::create_symlink("/dev/zero", tmp.path / name);
  struct Reader {
    const char* what;
    std::function<void(const std::string&)> read;
    const char* ext;
  };
  const std::vector<Reader> readers = {
      {"mesh", [](const std::string& p) { read_mesh(p); }, ".obj"},
      {"mesh ply", [](const std::string& p) { read_mesh(p); }, ".ply"},
      {"ply data", [](const std::string& p) { read_ply_data(p); }, ".ply"},
      {"texture", [](const std::string& p) { read_texture(p); }, ".ply"},
      {"edge values", [](const std::string& p) { read_edge_values(p, "label"); }, ".ply"},
      {"handles", [&](const std::string& p) { read_handles(p, X, 1.0); }, ".json"},
      {"features", [&](const std::string& p) { read_feature_file(p, cube); }, ".txt"},
      {"features ply", [&](const std::string& p) { read_feature_file(p, cube); }, ".ply"},
      {"points", [](const std::string& p) { read_point_file(p); }, ".xyz"},
      {"points obj", [](const std::string& p) { read_point_file(p); }, ".obj"},
      {"field", [&](const std::string& p) { read_field_file(p, cube.n_vertices()); }, ".txt"},
  };
  for (const auto& r : readers) {
    SCOPED_TRACE(r.what);
    const std::string fifo = tmp / (std::string("fifo") + r.ext), zero = tmp / (std::string("zero") + r.ext);
    EXPECT_EQ(in_child([&] { return io_error_with([&] { r.read(fifo); }, "is a FIFO (named pipe); geotex reads only regular files"); }), 0)
        << "FIFO (exit -1: blocked)";
    EXPECT_EQ(in_child([&] { return io_error_with([&] { r.read(zero); }, "is a device"); }), 0)
        << "/dev/zero (exit -1: read until killed)";
    const std::string dir = tmp / (std::string("dir") + r.ext);
    fs::create_directories(dir);
    EXPECT_EQ(in_child([&] { return io_error_with([&] { r.read(dir); }, "is a directory"); }), 0) << "a directory";
  }
}

TEST(ReaderQuirks, ReadRegularFileStopsAtItsLimit) {
  TempDir tmp;
  write_file(tmp / "a.txt", std::string(100, 'x'));
  EXPECT_EQ(read_regular_file(tmp / "a.txt", 100).size(), 100u);
  EXPECT_TRUE(throws_with<IoError>([&] { read_regular_file(tmp / "a.txt", 99, "a handles file"); }, "the limit for a handles file"));
  // /proc files say size 0: they are read to their end (and would stop at the limit).
  EXPECT_FALSE(read_regular_file("/proc/self/status").empty());
  EXPECT_THROW(read_regular_file("/proc/self/status", 10), IoError);
  EXPECT_TRUE(throws_with<IoError>([&] { read_regular_file(tmp / "missing.txt"); }, "no such file"));
}

TEST(ReaderQuirks, NonFiniteEdgeValuesAreRefused) {
  // A texture file's tilt (or an edge label) of NaN gave NaN meshes.
  TempDir tmp;
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\nelement edge 2\nproperty int vertex1\n"
                          "property int vertex2\nproperty double tilt\nend_header\n0 1 0.5\n1 2 nan\n";
  write_file(tmp / "t.ply", ply);
  EXPECT_TRUE(throws_with<InvalidInput>([&] { read_edge_values(tmp / "t.ply", "tilt"); }, "non-finite 'tilt'"));
}
