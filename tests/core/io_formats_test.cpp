// glTF 2.0, gzipped inputs, standard input and output, and the error lines of issue 30 (items 2, 3):
// what a reader says names the real cause, and it reads what a file held when it was opened.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::read_file;
using geotex::test::run_cli;
using geotex::test::TempDir;
using geotex::test::write_file;

namespace {

// A sphere whose coordinates are floats (glTF stores float32), so a round trip can be exact.
Mesh float_sphere() {
  Mesh m = icosphere(2, 1.0);
  MatrixX3d V = positions(m);
  for (Eigen::Index i = 0; i < V.size(); ++i) V.data()[i] = static_cast<float>(V.data()[i] * 1.7);
  set_positions(m, V);
  return m;
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= uint32_t(uint8_t(in[i + 2]));
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

template <class T>
void put(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// The buffer of the Khronos "Triangle" sample: three float positions, then ushort indices 0 1 2
// (padded to 4 bytes), then four more positions used as a strip and as a fan.
std::string triangle_buffer() {
  std::string b;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, f);  // 36 bytes
  for (uint16_t i : {0, 1, 2, 0}) put(b, i);                             // 8 bytes (last is padding)
  for (float f : {0.f, 0.f, 5.f, 1.f, 0.f, 5.f, 0.f, 1.f, 5.f, 1.f, 1.f, 5.f}) put(b, f);  // 48 bytes
  return b;
}

// A glTF as another tool exports it: a root node rotating +90 degrees about x (the Box sample's
// matrix), two instances of the triangle under it with their own translations, a point primitive,
// and a strip and a fan of the same four vertices in a second mesh.
std::string triangle_gltf(const std::string& uri) {
  return R"({
  "asset": {"version": "2.0", "generator": "hand-written like COLLADA2GLTF"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [
    {"children": [1, 2, 3], "matrix": [1,0,0,0, 0,0,1,0, 0,-1,0,0, 0,0,0,1]},
    {"mesh": 0, "translation": [10, 0, 0]},
    {"mesh": 0, "translation": [0, 0, 20], "scale": [2, 2, 2]},
    {"mesh": 1}
  ],
  "meshes": [
    {"primitives": [{"attributes": {"POSITION": 1}, "indices": 0},
                    {"attributes": {"POSITION": 1}, "mode": 0}]},
    {"primitives": [{"attributes": {"POSITION": 2}, "mode": 5},
                    {"attributes": {"POSITION": 2}, "mode": 6}]}
  ],
  "buffers": [{"uri": ")" + uri + R"(", "byteLength": 92}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 36, "byteLength": 6, "target": 34963},
    {"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 44, "byteLength": 48, "target": 34962}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5123, "count": 3, "type": "SCALAR", "max": [2], "min": [0]},
    {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3", "max": [1,1,0], "min": [0,0,0]},
    {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3", "max": [1,1,5], "min": [0,0,5]}
  ]
})";
}

// What the scene above holds, in scene coordinates: the root maps (x, y, z) to (x, -z, y).
void expect_triangle_scene(const Mesh& m, const ReadReport& rep) {
  const MatrixX3d V = positions(m);
  auto has = [&](double x, double y, double z) {
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      if (V(i, 0) == x && V(i, 1) == y && V(i, 2) == z) return true;
    return false;
  };
  // instance 1: translate (10, 0, 0), then rotate
  EXPECT_TRUE(has(10, 0, 0));
  EXPECT_TRUE(has(11, 0, 0));
  EXPECT_TRUE(has(10, 0, 1));
  // instance 2: scale 2, translate (0, 0, 20), then rotate: (0,0,0) -> (0, -20, 0), (0,1,0)*2 -> (0, -20, 2)
  EXPECT_TRUE(has(0, -20, 0));
  EXPECT_TRUE(has(2, -20, 0));
  EXPECT_TRUE(has(0, -20, 2));
  // mesh 1 (z = 5 -> y = -5): a strip and a fan of the same quad, 2 triangles each; the fan's
  // triangles duplicate the strip's or share its diagonal differently.
  EXPECT_TRUE(has(1, -5, 1));
  EXPECT_EQ(m.n_vertices(), 3u + 3u + 4u);  // equal positions are one vertex (the fan reuses the strip's)
  bool dropped_points = false;
  for (const auto& w : rep.warnings) dropped_points |= w.find("dropped 2 point primitive") != std::string::npos;  // one per instance
  EXPECT_TRUE(dropped_points) << "warnings must say the point primitive was dropped";
  EXPECT_EQ(rep.format, "gltf (.gltf)");
}

std::string escape_sh(const std::string& s) { return "'" + s + "'"; }

// A shell pipeline run as written (run_cli() redirects the last command's stdin from /dev/null).
test::CliResult sh(const std::string& pipeline, const TempDir& tmp) {
  const std::string out = tmp / "sh.out", err = tmp / "sh.err";
  const int status = std::system(("(" + pipeline + ") >" + out + " 2>" + err).c_str());
  test::CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

}  // namespace

TEST(Gltf, RoundTripIsExactInGlbAndGltf) {
  TempDir tmp;
  const Mesh m = float_sphere();
  for (const std::string name : {"s.glb", "s.gltf", "S.GLB"}) {
    write_mesh(m, tmp / name);
    ReadReport rep;
    const Mesh r = read_mesh(tmp / name, {}, &rep);
    ASSERT_EQ(r.n_vertices(), m.n_vertices()) << name;
    EXPECT_TRUE(positions(r) == positions(m)) << name;
    EXPECT_TRUE(faces(r) == faces(m)) << name;
    EXPECT_TRUE(rep.warnings.empty()) << name << ": " << rep.warnings.front();
  }
  // A .gltf is one file: its buffer is a data URI, so nothing else appears beside it.
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(tmp.path)) files += e.is_regular_file();
  EXPECT_EQ(files, 3u);
}

TEST(Gltf, WrittenFilesFollowTheSpec) {
  TempDir tmp;
  const Mesh m = float_sphere();
  write_mesh(m, tmp / "s.gltf");
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "s.gltf"));
  EXPECT_EQ(j["asset"]["version"], "2.0");
  const auto& pos = j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
  const auto& idx = j["accessors"][j["meshes"][0]["primitives"][0]["indices"].get<int>()];
  EXPECT_EQ(pos["componentType"], 5126);  // FLOAT
  EXPECT_EQ(pos["type"], "VEC3");
  EXPECT_EQ(idx["componentType"], 5125);  // UNSIGNED_INT
  EXPECT_EQ(idx["count"].get<size_t>(), 3 * m.n_faces());
  // min and max are required on POSITION and must be the bounds of the stored values.
  const MatrixX3d V = positions(m);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(pos["min"][k].get<double>(), V.col(k).minCoeff());
    EXPECT_EQ(pos["max"][k].get<double>(), V.col(k).maxCoeff());
  }
  EXPECT_EQ(j["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0), 0u);
  // GLB: magic, version 2, total length, a JSON chunk then a BIN chunk, 4-byte aligned (spec 4.4).
  write_mesh(m, tmp / "s.glb");
  const std::string b = read_file(tmp / "s.glb");
  uint32_t h[5];
  std::memcpy(h, b.data(), 20);
  EXPECT_EQ(b.substr(0, 4), "glTF");
  EXPECT_EQ(h[1], 2u);
  EXPECT_EQ(h[2], b.size());
  EXPECT_EQ(h[4], 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(h[3] % 4, 0u);
  uint32_t bin[2];
  std::memcpy(bin, b.data() + 20 + h[3], 8);
  EXPECT_EQ(bin[1], 0x004E4942u);  // "BIN\0"
  EXPECT_GE(bin[0], m.n_vertices() * 12 + m.n_faces() * 12);
}

TEST(Gltf, ReadsAnotherToolsSceneWithNodeTransformsStripsAndFans) {
  TempDir tmp;
  // data URI
  write_file(tmp / "tri.gltf", triangle_gltf("data:application/octet-stream;base64," + base64(triangle_buffer())));
  ReadReport rep;
  const Mesh a = read_mesh(tmp / "tri.gltf", {}, &rep);
  expect_triangle_scene(a, rep);
  // external .bin beside it
  std::filesystem::create_directory(tmp / "ext");
  write_file(tmp / "ext/tri.bin", triangle_buffer());
  write_file(tmp / "ext/tri.gltf", triangle_gltf("tri.bin"));
  ReadReport rep2;
  const Mesh b = read_mesh(tmp / "ext/tri.gltf", {}, &rep2);
  expect_triangle_scene(b, rep2);
  EXPECT_TRUE(positions(a) == positions(b));
  // a missing .bin is named
  std::filesystem::remove(tmp / "ext/tri.bin");
  try {
    read_mesh(tmp / "ext/tri.gltf");
    FAIL() << "a missing buffer file must be an error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("tri.bin"), std::string::npos) << e.what();
  }
}

TEST(Gltf, AMirroringTransformKeepsTheFacesOutward) {
  TempDir tmp;
  const Mesh m = float_sphere();
  write_mesh(m, tmp / "s.gltf");
  nlohmann::json j = nlohmann::json::parse(read_file(tmp / "s.gltf"));
  j["nodes"][0]["scale"] = {-1, 1, 1};
  write_file(tmp / "mirror.gltf", j.dump());
  const Mesh r = read_mesh(tmp / "mirror.gltf");
  // Outward faces of a sphere centred at the origin: the signed volume is positive.
  auto volume = [](const Mesh& mesh) {
    const MatrixX3d V = positions(mesh);
    const MatrixX3i F = faces(mesh);
    double v = 0;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      v += V.row(F(f, 0)).dot(V.row(F(f, 1)).cross(V.row(F(f, 2))));
    return v / 6;
  };
  EXPECT_GT(volume(m), 0);
  EXPECT_NEAR(volume(r), volume(m), 1e-9 * volume(m));
}

TEST(Gltf, BadFilesSayWhy) {
  TempDir tmp;
  write_file(tmp / "bad.glb", "glTF\x02\0\0\0garbage");
  write_file(tmp / "bad.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
  for (const std::string f : {"bad.glb", "bad.gltf"}) {
    EXPECT_THROW(read_mesh(tmp / f), IoError) << f;
    const auto r = run_cli("info " + (tmp / f));
    EXPECT_EQ(r.exit_code, 1) << f;
    EXPECT_NE(r.err.find("glTF"), std::string::npos) << f << ": " << r.err;
  }
  // Coordinates glTF cannot hold are refused before anything is written.
  Mesh big = float_sphere();
  MatrixX3d V = positions(big);
  V(0, 0) = 1e300;
  set_positions(big, V);
  EXPECT_THROW(write_mesh(big, tmp / "big.glb"), InvalidInput);
  EXPECT_FALSE(std::filesystem::exists(tmp / "big.glb"));
}

TEST(Gzip, ReadsGzippedPlyObjStlOff) {
  TempDir tmp;
  const Mesh m = float_sphere();
  for (const std::string ext : {"ply", "obj", "stl", "off"}) {
    const std::string f = tmp / ("s." + ext);
    write_mesh(m, f);
    ASSERT_EQ(std::system(("gzip -k " + escape_sh(f)).c_str()), 0);
    const Mesh r = read_mesh(f + ".gz");
    EXPECT_EQ(r.n_faces(), m.n_faces()) << ext;
    // STL repeats corners; merged back, its vertices come in another order.
    if (ext != "stl") EXPECT_TRUE(positions(r) == positions(m)) << ext;
    else EXPECT_TRUE(r.n_vertices() == m.n_vertices()) << ext;
  }
}

TEST(Gzip, CorruptTruncatedAndFakeGzipAreNamed) {
  TempDir tmp;
  write_mesh(float_sphere(), tmp / "s.ply");
  ASSERT_EQ(std::system(("gzip -k " + escape_sh(tmp / "s.ply")).c_str()), 0);
  const std::string gz = read_file(tmp / "s.ply.gz");
  write_file(tmp / "cut.ply.gz", gz.substr(0, gz.size() / 2));
  std::string bad = gz;
  for (size_t i = 40; i < 60; ++i) bad[i] = static_cast<char>(bad[i] ^ 0x5a);
  write_file(tmp / "bad.ply.gz", bad);
  write_file(tmp / "fake.ply.gz", read_file(tmp / "s.ply"));
  auto message = [&](const std::string& f) -> std::string {
    try {
      read_mesh(tmp / f);
    } catch (const IoError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(message("cut.ply.gz").find("truncated gzip"), std::string::npos) << message("cut.ply.gz");
  EXPECT_NE(message("bad.ply.gz").find("corrupt gzip"), std::string::npos) << message("bad.ply.gz");
  EXPECT_NE(message("fake.ply.gz").find("not gzip"), std::string::npos) << message("fake.ply.gz");
  for (const std::string f : {"cut.ply.gz", "bad.ply.gz", "fake.ply.gz"}) {
    const auto r = run_cli("info " + (tmp / f));
    EXPECT_EQ(r.exit_code, 1) << f << ": " << r.err;
    EXPECT_NE(r.err.find("gzip"), std::string::npos) << f << ": " << r.err;
  }
  // A bomb: content beyond the cap is refused, not allocated.
  EXPECT_THROW(gunzip(gz, "s.ply.gz", 1000), IoError);
  // Writing gzip is not offered, and says so.
  EXPECT_THROW(write_mesh(float_sphere(), tmp / "o.ply.gz"), IoError);
}

TEST(Stdio, FormatsAreSniffedFromTheirBytes) {
  TempDir tmp;
  const Mesh m = float_sphere();
  for (MeshFormat f : {MeshFormat::Ply, MeshFormat::Obj, MeshFormat::Off, MeshFormat::Stl, MeshFormat::Glb,
                       MeshFormat::Gltf}) {
    for (bool binary : {true, false}) {
      const std::string name = tmp / ("s." + format_name(f));
      WriteOptions o;
      o.binary = binary;
      write_mesh(m, name, o);
      EXPECT_EQ(sniff_format(read_file(name)), f) << format_name(f) << (binary ? " binary" : " ascii");
    }
  }
}

TEST(Stdio, PipesThroughStandardInputAndOutput) {
  TempDir tmp;
  const std::string cli = test::cli_path();
  // The brief's pipeline: generate to stdout, noise from stdin to stdout, info from stdin.
  const auto r = sh(cli + " generate cube -o - --format ply | " + cli + " noise - -o - --sigma 0.3 | " + cli +
                        " info - --json",
                    tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const Mesh cube = make_shape("cube", 1, 1).textured;
  EXPECT_EQ(j["vertices"].get<size_t>(), cube.n_vertices()) << r.out;
  // Every stdout format reads back through stdin; nothing but the mesh reaches stdout.
  for (const std::string f : {"ply", "obj", "off", "stl", "glb", "gltf"}) {
    const auto g = sh(cli + " generate sphere --level 0 --format " + f + " -o - > " + (tmp / "o.bin") + "; " + cli +
                          " smooth - -o " + (tmp / ("s." + f)) + " < " + (tmp / "o.bin"),
                      tmp);
    ASSERT_EQ(g.exit_code, 0) << f << ": " << g.err;
    const Mesh s = read_mesh(tmp / ("s." + f));
    EXPECT_EQ(s.n_faces(), make_shape("sphere", 0, 1).textured.n_faces()) << f;
    EXPECT_EQ(sniff_format(read_file(tmp / "o.bin")), format_from_name(f == "gltf" ? "gltf" : f)) << f;
  }
  // An empty pipe and a terminal-less empty stdin are named.
  const auto empty = sh(cli + " info - < /dev/null", tmp);
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.err.find("standard input"), std::string::npos) << empty.err;
  // --format is checked while parsing (a flag error).
  EXPECT_EQ(run_cli("generate cube -o - --format xyz").exit_code, 2);
}

TEST(Stdio, GltfAndGzipNamesAreCheckedBeforeAnyWork) {
  TempDir tmp;
  ASSERT_EQ(run_cli("generate cube -o " + (tmp / "c.glb")).exit_code, 0);
  ASSERT_EQ(run_cli("smooth " + (tmp / "c.glb") + " -o " + (tmp / "c.gltf")).exit_code, 0);
  EXPECT_EQ(read_mesh(tmp / "c.gltf").n_faces(), read_mesh(tmp / "c.glb").n_faces());
  const auto gz = run_cli("generate cube -o " + (tmp / "c.ply.gz"));
  EXPECT_EQ(gz.exit_code, 1);
  EXPECT_NE(gz.err.find("does not write them"), std::string::npos) << gz.err;
}

// Issue 30, item 2: error lines that name the real cause.
TEST(ErrorLines, NulInsideANumberIsShownNotCut) {
  TempDir tmp;
  const char raw[] = "v 0 0 0\nv 1\0.5 0 0\nv 0 1 0\nf 1 2 3\n";
  write_file(tmp / "nul.obj", std::string(raw, sizeof raw - 1));
  try {
    read_mesh(tmp / "nul.obj");
    FAIL() << "a NUL byte in a number must be an error";
  } catch (const IoError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("'1\\x00.5'"), std::string::npos) << w;
  }
  const auto r = run_cli("info " + (tmp / "nul.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(".5"), std::string::npos) << r.err;
}

TEST(ErrorLines, LoopsDevicesFifosAndFoldersSayWhatTheyAre) {
  TempDir tmp;
  std::filesystem::create_symlink(tmp / "b.obj", tmp / "a.obj");
  std::filesystem::create_symlink(tmp / "a.obj", tmp / "b.obj");
  std::filesystem::create_symlink("/dev/null", tmp / "null.ply");
  ASSERT_EQ(::mkfifo((tmp / "fifo.ply").c_str(), 0600), 0);
  std::filesystem::create_directory(tmp / "dir.obj");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"a.obj", "loop of symbolic links"}, {"null.ply", "a device"}, {"fifo.ply", "a FIFO"}, {"dir.obj", "is a directory"}};
  write_mesh(float_sphere(), tmp / "s.ply");
  for (const auto& [file, says] : cases) {
    try {
      read_mesh(tmp / file);
      ADD_FAILURE() << file << " must be refused";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    const auto r = run_cli("info " + (tmp / file));
    EXPECT_EQ(r.exit_code, 1) << file;
    EXPECT_NE(r.err.find(says), std::string::npos) << file << ": " << r.err;
    // side files: --edges and --field-file of render
    for (const std::string flag : {"--edges", "--field-file"}) {
      const auto s = run_cli("render " + (tmp / "s.ply") + " -o " + (tmp / "r.png") + " " + flag + " " + (tmp / file));
      EXPECT_EQ(s.exit_code, 1) << flag << " " << file << ": " << s.err;
      EXPECT_NE(s.err.find(says), std::string::npos) << flag << " " << file << ": " << s.err;
      EXPECT_EQ(s.err.find("no such file"), std::string::npos) << s.err;
    }
  }
}

TEST(ErrorLines, IndentedAsciiStlIsReadAsAscii) {
  TempDir tmp;
  std::string stl = "   solid indented\n";
  for (int t = 0; t < 2; ++t)
    stl += fmt::format("     facet normal 0 0 1\n       outer loop\n         vertex 0 0 {0}\n         vertex 1 0 {0}\n"
                       "         vertex 0 1 {0}\n       endloop\n     endfacet\n", t);
  stl += "   endsolid indented\n";
  write_file(tmp / "i.stl", stl);
  ReadReport rep;
  const Mesh m = read_mesh(tmp / "i.stl", {}, &rep);
  EXPECT_EQ(rep.format, "stl (ascii)");
  EXPECT_EQ(m.n_faces(), 2u);
  EXPECT_EQ(run_cli("info " + (tmp / "i.stl")).exit_code, 0);
}

// An index a PLY stores as a double is printed as the integer it is, not as 1.8446744073709552e+19.
TEST(ErrorLines, IndicesStoredAsDoublesArePrintedAsExactIntegers) {
  TempDir tmp;
  write_file(tmp / "f.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 1\nproperty list uchar double vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 18446744073709551615\n");
  write_file(tmp / "e.ply", "ply\nformat ascii 1.0\nelement edge 1\nproperty double vertex1\nproperty double vertex2\n"
                            "property int label\nend_header\n0 18446744073709551615 1\n");
  write_mesh(float_sphere(), tmp / "s.ply");
  // 2^64 - 1 has no double: the value read is 2^64, shown whole.
  const auto f = run_cli("info " + (tmp / "f.ply"));
  EXPECT_EQ(f.exit_code, 1);
  EXPECT_NE(f.err.find("vertex index 18446744073709551616,"), std::string::npos) << f.err;
  const auto e = run_cli("render " + (tmp / "s.ply") + " -o " + (tmp / "r.png") + " --edges " + (tmp / "e.ply"));
  EXPECT_EQ(e.exit_code, 1);
  EXPECT_NE(e.err.find("vertex 0 or 18446744073709551616,"), std::string::npos) << e.err;
  EXPECT_EQ(detail::exact_number(4294967297.0), "4294967297");
  EXPECT_EQ(detail::exact_number(2.5), "2.5");
}

// A writer appending "v 1 2 3" lines to \p path, 4 KiB at a time with \p pause between appends (none: as
// fast as it can), up to 256 MiB or until stop(): a file that keeps growing while it is read.
class Appender {
 public:
  explicit Appender(const std::string& path, std::chrono::microseconds pause = {}) : writer_([this, path, pause] {
    FILE* out = std::fopen(path.c_str(), "ab");
    std::string chunk;
    for (int i = 0; i < 512; ++i) chunk += "v 1 2 3\n";  // 4 KiB appends, whole lines
    std::setvbuf(out, nullptr, _IONBF, 0);
    while (!stop_ && appended_ < kLimit) {
      std::fwrite(chunk.data(), 1, chunk.size(), out);
      appended_ += chunk.size();
      if (pause.count() > 0) std::this_thread::sleep_for(pause);
    }
    std::fclose(out);
  }) {
    while (appended_ == 0) std::this_thread::yield();
  }
  ~Appender() { stop(); }
  void stop() {
    stop_ = true;
    if (writer_.joinable()) writer_.join();
  }
  size_t appended() const { return appended_; }
  static constexpr size_t kLimit = size_t(256) << 20;

 private:
  std::atomic<bool> stop_{false};
  std::atomic<size_t> appended_{0};
  std::thread writer_;
};

// Issue 30, item 3: a file that keeps growing is read as it was when opened.
TEST(GrowingFiles, ReadersStopAtWhatTheFileHeldWhenOpened) {
  TempDir tmp;
  const Mesh m = float_sphere();
  for (const std::string ext : {"ply", "obj", "off", "stl"}) {
    const std::string f = tmp / ("g." + ext);
    WriteOptions o;
    o.binary = false;
    write_mesh(m, f, o);
    // A writer appending (after the PLY's counts, more vertices to the OBJ) while the file is read.
    Appender writer(f);
    ReadReport rep;
    Mesh r;
    try {
      r = read_mesh(f, {}, &rep);
    } catch (const IoError& e) {
      // The size at open may end inside an appended line (OBJ): a truncated file, said as such.
      writer.stop();
      EXPECT_EQ(ext, "obj") << e.what();
      EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
      continue;
    }
    writer.stop();
    // The vertices the file had when it was opened: at most a few chunks more than written first
    // (OBJ), exactly the declared ones (PLY, OFF), and never the whole appended stream.
    EXPECT_EQ(r.n_faces(), m.n_faces()) << ext;
    EXPECT_LT(rep.file_vertices, m.n_vertices() + (size_t(64) << 20) / 8) << ext;
    if (ext != "obj") EXPECT_EQ(rep.file_vertices, m.n_vertices()) << ext;
  }
}

// Issue 30, item 3, through standard input: a pipe has no size to snapshot. A PLY (or OFF) is read up to
// its declared counts, whether the writer goes on fast (it is cut off: SIGPIPE) or appends a line now and
// then (a writer still busy, tail -f); a file given as `< FILE` is read as large as it was at the start.
TEST(GrowingFiles, StandardInputStopsAtTheDeclaredCounts) {
  TempDir tmp;
  const Mesh m = float_sphere();
  const std::string cli = test::cli_path();
  WriteOptions ascii;
  ascii.binary = false;
  write_mesh(m, tmp / "a.ply", ascii);
  write_mesh(m, tmp / "b.ply");
  write_mesh(m, tmp / "a.off");
  for (const std::string f : {"a.ply", "b.ply", "a.off"}) {
    // A fast writer: 256 MiB of rows after the mesh. Main read them all (the writer finished, status 0).
    const std::string rc = tmp / (f + ".writer");
    const auto fast = sh("(cat " + (tmp / f) + "; yes '1 2 3' | head -c 268435456; echo $? > " + rc + ") | " + cli +
                             " info - --json",
                         tmp);
    ASSERT_EQ(fast.exit_code, 0) << f << ": " << fast.err;
    EXPECT_EQ(nlohmann::json::parse(fast.out)["vertices"].get<size_t>(), m.n_vertices()) << f;
    EXPECT_EQ(read_file(rc), "141\n") << f << ": the writer was not cut off (SIGPIPE), so all of it was read";
    // A writer that never ends, appending a line every 0.2 s: main waited for its end (the 120 s guard).
    const auto slow = sh("(cat " + (tmp / f) + "; while printf '1 2 3\\n'; do sleep 0.2; done) | timeout 120 " + cli +
                             " info - --json",
                         tmp);
    ASSERT_EQ(slow.exit_code, 0) << f << ": " << slow.err;
    EXPECT_EQ(nlohmann::json::parse(slow.out)["faces"].get<size_t>(), m.n_faces()) << f;
  }
  // `< FILE` while another process appends to it (whole lines, more vertices of an OBJ).
  write_mesh(m, tmp / "g.obj", ascii);
  {
    // Page-aligned whole-page appends: a page is the unit in which a reader sees a regular file grow (a
    // write across two pages can be seen half done, a line cut, which the reader rightly calls truncated).
    const size_t size = std::filesystem::file_size(tmp / "g.obj");
    size_t pad = (4096 - size % 4096) % 4096;
    if (pad == 1) pad += 4096;
    if (pad > 0) {
      std::ofstream f(tmp / "g.obj", std::ios::app | std::ios::binary);
      f << '#' << std::string(pad - 2, ' ') << '\n';
    }
  }
  // 4 MiB/s: still growing when geotex is done (as fast as it can, it reached 256 MiB before geotex started).
  Appender writer(tmp / "g.obj", std::chrono::milliseconds(1));
  const auto r = sh(cli + " info - --json < " + (tmp / "g.obj"), tmp);
  const size_t at_exit = writer.appended();  // what had been appended when geotex was done
  writer.stop();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["faces"].get<size_t>(), m.n_faces());
  // Read no further than the file had grown when geotex finished (8 bytes per appended vertex line); the
  // bound is taken when geotex exits, not fixed, so a loaded machine that starts geotex late does not fail it.
  EXPECT_LE(nlohmann::json::parse(r.out)["vertices"].get<size_t>(), m.n_vertices() + at_exit / 8);
  if (at_exit >= Appender::kLimit)
    GTEST_SKIP() << "the writer reached its 256 MiB before geotex finished: this run did not show that a growing "
                    "file stops the read";
}
