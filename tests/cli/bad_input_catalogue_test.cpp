// The bad-input catalogue (docs/bad-input.md): one test per row, mostly through the real command line,
// so that each row states what a user sees. A row passes when geotex either stops with exit code 1
// and one clear line, or repairs/continues with a warning and a sound result — never a crash, a
// hang, silent garbage or a damaged input file.

#include <map>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <cstring>
#include <string>

#include <sys/stat.h>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/smoothing.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::CliResult;
using geotex::test::read_file;
using geotex::test::run_cli;
using geotex::test::TempDir;
using geotex::test::write_file;
namespace fs = std::filesystem;

namespace {

// Exit code 1 and one error line on stderr ("geotex: ..." containing `needle`), besides any reader
// warnings ("geotex: warning: ...") that came before it.
::testing::AssertionResult one_line_error(const CliResult& r, const std::string& needle = "") {
  if (r.exit_code != 1) return ::testing::AssertionFailure() << "exit code " << r.exit_code << ", stderr: " << r.err;
  std::vector<std::string> errors;
  std::istringstream in(r.err);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("geotex: warning: ", 0) != 0 && line.rfind("geotex: note: ", 0) != 0) errors.push_back(line);
  if (errors.size() != 1 || r.err.back() != '\n') return ::testing::AssertionFailure() << "not one error line: " << r.err;
  if (errors[0].rfind("geotex: ", 0) != 0) return ::testing::AssertionFailure() << "no 'geotex: ' prefix: " << r.err;
  if (!needle.empty() && errors[0].find(needle) == std::string::npos)
    return ::testing::AssertionFailure() << "no '" << needle << "' in: " << r.err;
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult ok_with(const CliResult& r, const std::string& needle) {
  if (r.exit_code != 0) return ::testing::AssertionFailure() << "exit code " << r.exit_code << ", stderr: " << r.err;
  if (r.err.find(needle) == std::string::npos) return ::testing::AssertionFailure() << "no '" << needle << "' in: " << r.err;
  return ::testing::AssertionSuccess();
}

// No control characters but the line ends (bytes >= 0x80 may be UTF-8 in file names).
bool printable(const std::string& s) {
  return std::none_of(s.begin(), s.end(), [](char ch) {
    const auto c = static_cast<unsigned char>(ch);
    return (c < 0x20 && c != '\n') || c == 0x7f;
  });
}

nlohmann::json info_json(const std::string& path) {
  const CliResult r = run_cli("-q info --json " + path);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json{};
}

// OBJ text of a mesh (positions in full), plus extra lines.
std::string obj_of(const Mesh& m, const std::string& extra = "") {
  std::string s;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    s += fmt::format("v {} {} {}\n", p[0], p[1], p[2]);
  }
  for (auto f : m.faces()) {
    s += 'f';
    for (auto v : f.vertices()) s += ' ' + std::to_string(v.idx() + 1);
    s += '\n';
  }
  return s + extra;
}

bool all_finite(const Mesh& m) { return positions(m).allFinite(); }

const char* const kFormats[] = {"obj", "ply", "off", "stl"};

}  // namespace

// ---- empty file -------------------------------------------------------------------------------

TEST(BadInputCatalogue, EmptyOrBlankFileIsAOneLineError) {
  TempDir tmp;
  for (const char* ext : kFormats) {
    const std::string f = tmp / (std::string("empty.") + ext);
    write_file(f, "");
    EXPECT_TRUE(one_line_error(run_cli("info " + f), "empty")) << ext;
    EXPECT_TRUE(one_line_error(run_cli("smooth " + f + " -o " + (tmp / "out.ply")), "empty")) << ext;
    EXPECT_FALSE(fs::exists(tmp / "out.ply"));
  }
  // Whitespace only is as empty as nothing.
  write_file(tmp / "blank.obj", "\n\n  \n");
  EXPECT_TRUE(one_line_error(run_cli("info " + (tmp / "blank.obj")), "no vertices"));
}

// ---- binary garbage ---------------------------------------------------------------------------

TEST(BadInputCatalogue, BinaryGarbageGivesOnePrintableErrorLine) {
  TempDir tmp;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    std::string bytes(4096 + 777 * trial, '\0');
    for (auto& c : bytes) c = static_cast<char>(rng() & 0xff);
    // Also garbage behind each format's magic word, so the parsers get past their first check.
    const std::string prefixes[] = {"", "ply\nformat binary_little_endian 1.0\n", "OFF\n", "solid x\n", "v 1 2 3\nf "};
    for (const char* ext : kFormats) {
      for (const auto& p : prefixes) {
        const std::string f = tmp / (std::string("garbage.") + ext);
        write_file(f, p + bytes);
        const CliResult r = run_cli("info " + f);
        EXPECT_TRUE(one_line_error(r)) << ext << " trial " << trial << " prefix '" << p << "'";
        EXPECT_TRUE(printable(r.err)) << r.err;
      }
    }
  }
  // Bytes quoted from the file are shown escaped: a terminal escape sequence cannot act.
  write_file(tmp / "esc.obj", "v 0 0 \x1b[2J\x07\n");
  const CliResult r = run_cli("info " + (tmp / "esc.obj"));
  EXPECT_TRUE(one_line_error(r, "\\x1b[2J\\x07")) << r.err;
  EXPECT_TRUE(printable(r.err));
  // A huge garbage token gives a line of bounded length.
  write_file(tmp / "long.obj", "v 0 0 " + std::string(100000, 'x') + "\n");
  const CliResult l = run_cli("info " + (tmp / "long.obj"));
  EXPECT_TRUE(one_line_error(l));
  EXPECT_LT(l.err.size(), 1200u);
}

// ---- truncated files --------------------------------------------------------------------------

// Binary PLY, binary STL and OFF/ascii PLY declare their counts: any cut is an error naming the
// truncation (or, inside a number, the malformed line). OBJ has no counts: a cut inside a line is an
// error; a cut that leaves a well-formed last line reads what is there, with a warning that the last
// line has no end-of-line.
TEST(BadInputCatalogue, TruncatedFileIsAnErrorOrReadWithAWarning) {
  TempDir tmp;
  const Mesh m = icosphere(2);
  struct Fmt {
    std::string name, file;
    bool binary;
    bool counts;  // the format declares how much follows
  };
  const Fmt fmts[] = {{"obj", "s.obj", false, false},       {"ascii ply", "s.ply", false, true},
                      {"binary ply", "s.ply", true, true},  {"off", "s.off", false, true},
                      {"binary stl", "s.stl", true, true},  {"ascii stl", "s.stl", false, true}};
  for (const auto& f : fmts) {
    WriteOptions w;
    w.binary = f.binary;
    write_mesh(m, tmp / f.file, w);
    const std::string full = read_file(tmp / f.file);
    for (double frac : {0.02, 0.3, 0.5, 0.77, 0.99}) {
      const size_t cut = std::max<size_t>(1, static_cast<size_t>(frac * full.size()));
      const std::string t = tmp / ("cut-" + f.file);
      write_file(t, full.substr(0, cut));
      const CliResult r = run_cli("info " + t);
      SCOPED_TRACE(f.name + " cut at " + std::to_string(cut) + " of " + std::to_string(full.size()));
      if (r.exit_code == 0) {
        // Only a text format may read on, and then it must say the file may be truncated.
        EXPECT_FALSE(f.binary);
        EXPECT_NE(r.err.find("may be truncated"), std::string::npos) << r.err;
      } else {
        EXPECT_TRUE(one_line_error(r));
        if (f.binary) EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
      }
    }
  }
  // The same cut through the library: binary formats name the truncation.
  write_mesh(m, tmp / "b.ply");
  const std::string ply = read_file(tmp / "b.ply");
  write_file(tmp / "c.ply", ply.substr(0, ply.size() - 5));
  EXPECT_THROW(read_mesh(tmp / "c.ply"), IoError);
}

// ---- NaN / inf coordinates --------------------------------------------------------------------

TEST(BadInputCatalogue, NonFiniteCoordinatesAreRefused) {
  TempDir tmp;
  write_file(tmp / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  write_file(tmp / "inf.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n1 1 0\n3 0 1 2\n");
  write_file(tmp / "neginf.obj", "v 0 0 0\nv 1 0 -Infinity\nv 0 1 0\nf 1 2 3\n");
  // Binary PLY with a float NaN and binary STL with a float +inf.
  {
    Mesh m = icosphere(0);
    MatrixX3d V = positions(m);
    V(3, 1) = std::numeric_limits<double>::quiet_NaN();
    // write_mesh does not check finiteness: write a valid mesh and patch the bytes.
    write_mesh(m, tmp / "nan.ply");
    std::string b = read_file(tmp / "nan.ply");
    const size_t body = b.find("end_header\n") + 11;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(&b[body + 3 * 8 * 3 + 8], &nan, 8);
    write_file(tmp / "nan.ply", b);
    write_mesh(m, tmp / "inf.stl");
    std::string s = read_file(tmp / "inf.stl");
    const float inf = std::numeric_limits<float>::infinity();
    std::memcpy(&s[84 + 12], &inf, 4);
    write_file(tmp / "inf.stl", s);
  }
  for (const char* f : {"nan.obj", "inf.off", "neginf.obj", "nan.ply", "inf.stl"}) {
    EXPECT_TRUE(one_line_error(run_cli("info " + (tmp / f)), "non-finite")) << f;
    EXPECT_TRUE(one_line_error(run_cli("smooth " + (tmp / f) + " -o " + (tmp / "o.obj")), "non-finite")) << f;
    EXPECT_FALSE(fs::exists(tmp / "o.obj"));
  }
  // Library: make_mesh refuses non-finite positions too.
  MatrixX3d V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, std::nan(""), 0;
  MatrixX3i F(1, 3);
  F << 0, 1, 2;
  EXPECT_THROW(make_mesh(V, F), InvalidInput);
}

// ---- duplicate faces --------------------------------------------------------------------------

TEST(BadInputCatalogue, DuplicateFacesAreDroppedAndReported) {
  TempDir tmp;
  const Mesh m = icosphere(1);
  // The first face again, once as is and once reversed.
  write_file(tmp / "dup.obj", obj_of(m, "f 1 2 3\nf 3 2 1\n").replace(0, 0, ""));
  const Mesh first = icosphere(1);
  const auto F = faces(first);
  const std::string again = fmt::format("f {} {} {}\nf {} {} {}\n", F(0, 0) + 1, F(0, 1) + 1, F(0, 2) + 1,
                                        F(0, 2) + 1, F(0, 1) + 1, F(0, 0) + 1);
  write_file(tmp / "dup.obj", obj_of(m, again));
  const CliResult r = run_cli("info " + (tmp / "dup.obj"));
  EXPECT_TRUE(ok_with(r, "dropped 2 duplicate face(s)"));
  const auto j = info_json(tmp / "dup.obj");
  EXPECT_EQ(j["faces"].get<size_t>(), m.n_faces());
  EXPECT_EQ(j["read"]["dropped_duplicate_faces"].get<int>(), 2);
  EXPECT_TRUE(j["closed"].get<bool>());  // what is left is the sphere, closed
  EXPECT_TRUE(one_line_error(run_cli("info --strict " + (tmp / "dup.obj")), "strict"));
}

// ---- degenerate faces -------------------------------------------------------------------------

TEST(BadInputCatalogue, DegenerateFacesRepeatedIndex) {
  TempDir tmp;
  const Mesh m = icosphere(1);
  write_file(tmp / "deg.obj", obj_of(m, "f 1 1 2\nf 3 4 3\n"));
  EXPECT_TRUE(ok_with(run_cli("info " + (tmp / "deg.obj")), "dropped 2 degenerate face(s)"));
  const auto j = info_json(tmp / "deg.obj");
  EXPECT_EQ(j["faces"].get<size_t>(), m.n_faces());
  EXPECT_EQ(j["read"]["dropped_degenerate_faces"].get<int>(), 2);
  EXPECT_TRUE(one_line_error(run_cli("info --strict " + (tmp / "deg.obj")), "degenerate"));
}

// Zero-area faces with three distinct vertices (collinear corners, or two corners at one point) are
// valid connectivity: they are kept, counted by `info`, and every command stays finite (see also
// ZeroAreaCotanWeights).
TEST(BadInputCatalogue, DegenerateFacesZeroArea) {
  TempDir tmp;
  // A 4x4 grid whose middle row is squashed onto the row below: a strip of collinear triangles.
  Mesh m = plane(4);
  MatrixX3d V = positions(m);
  const double y_mid = 0.5 * (V.col(1).minCoeff() + V.col(1).maxCoeff());
  const double step = (V.col(1).maxCoeff() - V.col(1).minCoeff()) / 4;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (std::abs(V(i, 1) - y_mid) < 1e-9) V(i, 1) -= step;  // onto the row below: zero-area faces
  set_positions(m, V);
  write_mesh(m, tmp / "flat.ply");
  const CliResult r = run_cli("info " + (tmp / "flat.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("zero-area"), std::string::npos) << r.out;
  const auto j = info_json(tmp / "flat.ply");
  EXPECT_GT(j["zero_area_faces"].get<int>(), 0);
  EXPECT_EQ(j["faces"].get<size_t>(), m.n_faces());  // kept
  for (const char* lap : {"cotan", "umbrella"}) {
    const CliResult s = run_cli("smooth " + (tmp / "flat.ply") + " -o " + (tmp / "s.ply") + " --laplacian " + lap);
    ASSERT_EQ(s.exit_code, 0) << lap << ": " << s.err;
    EXPECT_TRUE(all_finite(read_mesh(tmp / "s.ply"))) << lap;
  }
}

// ---- isolated vertices ------------------------------------------------------------------------

TEST(BadInputCatalogue, IsolatedVerticesAreKeptInPlace) {
  TempDir tmp;
  const Mesh m = icosphere(2);
  write_file(tmp / "iso.obj", obj_of(m, "v 5 5 5\nv -5 0 0\n"));
  EXPECT_TRUE(ok_with(run_cli("info " + (tmp / "iso.obj")), "2 vertex(es) belong to no face (kept)"));
  const auto j = info_json(tmp / "iso.obj");
  EXPECT_EQ(j["isolated_vertices"].get<int>(), 2);
  EXPECT_EQ(j["vertices"].get<size_t>(), m.n_vertices() + 2);  // kept, so vertex indices stay valid
  // Commands run; the isolated vertices stay where they are and everything stays finite.
  const std::string in = tmp / "iso.obj";
  for (const std::string cmd : {"smooth " + in + " -o " + (tmp / "out.obj"),
                                "smooth " + in + " -o " + (tmp / "out.obj") + " --laplacian umbrella --explicit",
                                "noise " + in + " -o " + (tmp / "out.obj") + " --sigma 0.1",
                                "denoise " + in + " -o " + (tmp / "out.obj") + " --method mrf --iterations 2",
                                "denoise " + in + " -o " + (tmp / "out.obj") + " --method mrf-normal --iterations 2"}) {
    const CliResult r = run_cli("-q " + cmd);
    ASSERT_EQ(r.exit_code, 0) << cmd << "\n" << r.err;
    const Mesh out = read_mesh(tmp / "out.obj");
    EXPECT_TRUE(all_finite(out)) << cmd;
    if (out.n_vertices() == m.n_vertices() + 2 && cmd.rfind("noise", 0) != 0) {
      EXPECT_EQ(to_eigen(out.point(out.vertex_handle(m.n_vertices()))), Vec3(5, 5, 5)) << cmd;
    }
  }
  // A parametrization needs every vertex in the disk.
  write_file(tmp / "patch.obj", obj_of(plane(4), "v 9 9 9\n"));
  EXPECT_TRUE(one_line_error(run_cli("param " + (tmp / "patch.obj") + " -o " + (tmp / "uv.obj")), "isolated"));
}

// ---- non-manifold edges -----------------------------------------------------------------------

TEST(BadInputCatalogue, NonManifoldEdgeKeepsItsFirstTwoFaces) {
  TempDir tmp;
  // A closed tetrahedron plus a fin: a third face on edge (1, 2).
  write_file(tmp / "fin.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n"
             "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\nf 1 2 5\n");
  const CliResult r = run_cli("info " + (tmp / "fin.obj"));
  EXPECT_TRUE(ok_with(r, "dropped 1 non-manifold face(s)"));
  EXPECT_NE(r.out.find("manifold       no"), std::string::npos) << r.out;
  const auto j = info_json(tmp / "fin.obj");
  EXPECT_EQ(j["faces"].get<int>(), 4);
  EXPECT_TRUE(j["closed"].get<bool>());  // the first two faces on the edge are kept: the tetrahedron
  EXPECT_EQ(j["read"]["dropped_nonmanifold_faces"].get<int>(), 1);
  EXPECT_FALSE(j["manifold"].get<bool>());
  EXPECT_TRUE(one_line_error(run_cli("info --strict " + (tmp / "fin.obj")), "non-manifold"));
  EXPECT_EQ(run_cli("-q smooth " + (tmp / "fin.obj") + " -o " + (tmp / "s.obj")).exit_code, 0);
}

// ---- non-manifold vertices --------------------------------------------------------------------

// Two closed fans (two double cones) sharing their apex, and two triangles touching at one corner
// (a bow tie): the vertex is split, one copy per fan, and no face is lost.
TEST(BadInputCatalogue, NonManifoldVertexIsSplitWithoutLosingAFace) {
  TempDir tmp;
  // Two octahedra touching at vertex 1 (the origin).
  std::string s = "v 0 0 0\n";
  // first octahedron: centre (0,0,1), apex at origin
  s += "v 1 0 1\nv 0 1 1\nv -1 0 1\nv 0 -1 1\nv 0 0 2\n";
  // second octahedron: centre (0,0,-1)
  s += "v 1 0 -1\nv 0 1 -1\nv -1 0 -1\nv 0 -1 -1\nv 0 0 -2\n";
  for (int o : {0, 5}) {
    const int r0 = 2 + o, top = 6 + o;
    for (int k = 0; k < 4; ++k) {
      const int a = r0 + k, b = r0 + (k + 1) % 4;
      if (o == 0) s += fmt::format("f 1 {} {}\nf {} {} {}\n", b, a, a, b, top);
      else s += fmt::format("f 1 {} {}\nf {} {} {}\n", a, b, b, a, top);
    }
  }
  write_file(tmp / "pinch.obj", s);
  const CliResult r = run_cli("info " + (tmp / "pinch.obj"));
  EXPECT_TRUE(ok_with(r, "split 1 non-manifold vertex(es)")) << r.err;
  const auto j = info_json(tmp / "pinch.obj");
  EXPECT_EQ(j["faces"].get<int>(), 16);     // no face lost
  EXPECT_EQ(j["vertices"].get<int>(), 12);  // one copy of the apex, appended
  EXPECT_EQ(j["components"].get<int>(), 2);
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_TRUE(one_line_error(run_cli("info --strict " + (tmp / "pinch.obj")), "non-manifold"));

  // Bow tie: OpenMesh would accept it as is; geotex splits it too.
  write_file(tmp / "bowtie.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n");
  EXPECT_TRUE(ok_with(run_cli("info " + (tmp / "bowtie.obj")), "split 1 non-manifold vertex(es)"));
  const auto b = info_json(tmp / "bowtie.obj");
  EXPECT_EQ(b["faces"].get<int>(), 2);
  EXPECT_EQ(b["vertices"].get<int>(), 6);
  EXPECT_EQ(b["boundary_loops"].get<int>(), 2);

  // Library: the copies come after the input's vertices, at the same place.
  ReadReport rep;
  const Mesh mesh = read_mesh(tmp / "pinch.obj", {}, &rep);
  EXPECT_EQ(rep.build.split_vertices, 1u);
  EXPECT_EQ(rep.build.added_vertices, 1u);
  EXPECT_EQ(rep.build.nonmanifold_vertices, 0u);
  EXPECT_EQ(to_eigen(mesh.point(mesh.vertex_handle(11))), Vec3(0, 0, 0));
  for (auto v : mesh.vertices()) EXPECT_TRUE(mesh.is_manifold(v));
  // Without the repair the second fan's faces are dropped and reported.
  ReadOptions no_repair;
  no_repair.repair = false;
  const Mesh dropped = read_mesh(tmp / "pinch.obj", no_repair, &rep);
  EXPECT_LT(dropped.n_faces(), 16u);
  EXPECT_GT(rep.build.nonmanifold_faces, 0u);
}

// ---- inconsistent orientation -----------------------------------------------------------------

TEST(BadInputCatalogue, InconsistentOrientationTurnsToTheMajority) {
  TempDir tmp;
  const Mesh m = icosphere(2);
  const double volume = signed_volume(m);
  ASSERT_GT(volume, 0);
  // Flip a few faces (reverse their corner order) in the file.
  Mesh flipped_file = m;
  MatrixX3i F = faces(m);
  for (int f : {0, 7, 33, 100}) std::swap(F(f, 1), F(f, 2));
  std::string s;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    s += fmt::format("v {} {} {}\n", p[0], p[1], p[2]);
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) s += fmt::format("f {} {} {}\n", F(f, 0) + 1, F(f, 1) + 1, F(f, 2) + 1);
  write_file(tmp / "flip.obj", s);
  EXPECT_TRUE(ok_with(run_cli("info " + (tmp / "flip.obj")), "turned 4 face(s) round"));
  const auto j = info_json(tmp / "flip.obj");
  EXPECT_EQ(j["faces"].get<size_t>(), m.n_faces());  // nothing dropped: no hole
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_NEAR(j["volume"].get<double>(), volume, 1e-12);  // the majority (outward) orientation wins
  // Even when most faces are flipped, the mesh comes back consistent (here: all inward).
  for (Eigen::Index f = 0; f < F.rows(); ++f) std::swap(F(f, 1), F(f, 2));
  s.clear();
  for (auto v : m.vertices()) s += fmt::format("v {} {} {}\n", m.point(v)[0], m.point(v)[1], m.point(v)[2]);
  for (Eigen::Index f = 0; f < F.rows(); ++f) s += fmt::format("f {} {} {}\n", F(f, 0) + 1, F(f, 1) + 1, F(f, 2) + 1);
  write_file(tmp / "mostly-inward.obj", s);
  EXPECT_NEAR(info_json(tmp / "mostly-inward.obj")["volume"].get<double>(), -volume, 1e-12);
  EXPECT_TRUE(one_line_error(run_cli("info --strict " + (tmp / "flip.obj")), "round"));
  // Smoothing the repaired mesh behaves like smoothing the clean one.
  ASSERT_EQ(run_cli("-q smooth " + (tmp / "flip.obj") + " -o " + (tmp / "a.ply")).exit_code, 0);
  write_mesh(m, tmp / "clean.ply");
  ASSERT_EQ(run_cli("-q smooth " + (tmp / "clean.ply") + " -o " + (tmp / "b.ply")).exit_code, 0);
  EXPECT_LT((positions(read_mesh(tmp / "a.ply")) - positions(read_mesh(tmp / "b.ply"))).cwiseAbs().maxCoeff(), 1e-9);
}

// A Möbius strip cannot be oriented: one face stays refused and is reported, nothing crashes.
TEST(BadInputCatalogue, NonOrientableSurfaceDropsOneFaceAndSaysSo) {
  TempDir tmp;
  std::string s;
  const int n = 12;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n, a = t / 2;
    for (double w : {-0.2, 0.2}) {
      const double r = 1 + w * std::cos(a);
      s += fmt::format("v {} {} {}\n", r * std::cos(t), r * std::sin(t), w * std::sin(a));
    }
  }
  for (int i = 0; i < n; ++i) {
    const int a0 = 2 * i + 1, a1 = 2 * i + 2;
    int b0 = 2 * ((i + 1) % n) + 1, b1 = 2 * ((i + 1) % n) + 2;
    if (i == n - 1) std::swap(b0, b1);  // the half twist
    s += fmt::format("f {} {} {}\nf {} {} {}\n", a0, b0, b1, a0, b1, a1);
  }
  write_file(tmp / "moebius.obj", s);
  const CliResult r = run_cli("info " + (tmp / "moebius.obj"));
  EXPECT_TRUE(ok_with(r, "non-manifold face(s)")) << r.err;
  EXPECT_EQ(info_json(tmp / "moebius.obj")["faces"].get<int>(), 2 * n - 1);
}

// The repairs on random soups over few vertices (every kind of non-manifoldness at once): no crash,
// every face is kept or counted as dropped, copies are appended and used, the input's vertices stay put.
TEST(BadInputCatalogue, RandomSoupsAreRepairedOrReported) {
  std::mt19937 rng(11);
  BuildOptions repair;
  repair.fix_orientation = repair.split_nonmanifold_vertices = true;
  for (int trial = 0; trial < 300; ++trial) {
    const int nv = 4 + trial % 20, nf = 1 + static_cast<int>(rng() % 60);
    MatrixX3d V = MatrixX3d::Random(nv, 3);
    MatrixX3i F(nf, 3);
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) F(f, k) = static_cast<int>(rng() % nv);
    BuildReport rep;
    const Mesh m = make_mesh(V, F, &rep, repair);
    ASSERT_EQ(m.n_faces() + rep.dropped(), static_cast<size_t>(nf)) << "trial " << trial;
    ASSERT_EQ(m.n_vertices(), nv + rep.added_vertices) << "trial " << trial;
    for (size_t i = nv; i < m.n_vertices(); ++i) ASSERT_FALSE(m.is_isolated(m.vertex_handle(i)));
    ASSERT_TRUE(positions(m).topRows(nv) == V);
    for (auto h : m.halfedges()) ASSERT_TRUE(m.next_halfedge_handle(h).is_valid());
  }
}

// ---- several components -----------------------------------------------------------------------

TEST(BadInputCatalogue, SeveralComponentsRunExceptWhereOneDiskIsNeeded) {
  TempDir tmp;
  Mesh a = icosphere(2), b = icosphere(2, 0.5);
  const MatrixX3d Va = positions(a), Vb = positions(b).rowwise() + Eigen::RowVector3d(3, 0, 0);
  const MatrixX3i Fa = faces(a), Fb = faces(b);
  MatrixX3d V(Va.rows() + Vb.rows(), 3);
  V << Va, Vb;
  MatrixX3i F(Fa.rows() + Fb.rows(), 3);
  F << Fa, (Fb.array() + static_cast<int>(Va.rows())).matrix();
  write_mesh(make_mesh(V, F), tmp / "two.ply");
  const auto j = info_json(tmp / "two.ply");
  EXPECT_EQ(j["components"].get<int>(), 2);
  EXPECT_TRUE(j["genus"].is_null());  // genus is per component
  const CliResult r = run_cli("info " + (tmp / "two.ply"));
  EXPECT_NE(r.out.find("n/a (several components)"), std::string::npos) << r.out;
  // Per-vertex commands work on each component.
  ASSERT_EQ(run_cli("-q smooth " + (tmp / "two.ply") + " -o " + (tmp / "s.ply") + " --rescale").exit_code, 0);
  const Mesh s = read_mesh(tmp / "s.ply");
  EXPECT_TRUE(all_finite(s));
  ASSERT_EQ(run_cli("-q denoise " + (tmp / "two.ply") + " -o " + (tmp / "d.ply") + " --method mrf --iterations 2").exit_code, 0);
  // A parametrization needs one disk.
  Mesh p = plane(3), q = plane(3);
  const MatrixX3d Vp = positions(p), Vq = positions(q).rowwise() + Eigen::RowVector3d(5, 0, 0);
  MatrixX3d V2(Vp.rows() * 2, 3);
  V2 << Vp, Vq;
  MatrixX3i F2(faces(p).rows() * 2, 3);
  F2 << faces(p), (faces(q).array() + static_cast<int>(Vp.rows())).matrix();
  write_mesh(make_mesh(V2, F2), tmp / "two-disks.obj");
  EXPECT_TRUE(one_line_error(run_cli("param " + (tmp / "two-disks.obj") + " -o " + (tmp / "uv.obj")), "component"));
}

// ---- boundaries where a closed surface would be needed ----------------------------------------

// No geotex command requires a closed surface: every per-mesh command runs on an open patch (a
// plane and a hemisphere-like spiky plane), with the boundary fixed where the method needs it.
TEST(BadInputCatalogue, EveryCommandRunsOnAnOpenMesh) {
  TempDir tmp;
  ASSERT_EQ(run_cli("-q generate spiky-plane --level 0 -o " + (tmp / "sp.ply") + " --base-output " + (tmp / "base.ply")).exit_code, 0);
  ASSERT_EQ(run_cli("-q noise " + (tmp / "base.ply") + " -o " + (tmp / "n.ply") + " --sigma 0.2").exit_code, 0);
  const std::string n = tmp / "n.ply", sp = tmp / "sp.ply";
  const std::string cmds[] = {
      "smooth " + n + " -o " + (tmp / "o1.ply"),
      "smooth " + n + " -o " + (tmp / "o1.ply") + " --rescale --move-boundary",
      "denoise " + n + " -o " + (tmp / "o2.ply") + " --method mrf --iterations 3",
      "denoise " + n + " -o " + (tmp / "o3.ply") + " --method mrf-normal --iterations 3",
      "denoise " + n + " -o " + (tmp / "o4.ply") + " --method surfel",
      "param " + n + " -o " + (tmp / "o5.obj"),
      "texture extract " + sp + " -o " + (tmp / "t.ply") + " --steps 3",
      "resize " + sp + " -o " + (tmp / "o6.ply") + " --scale 2,1,1",
  };
  for (const auto& c : cmds) {
    const CliResult r = run_cli("-q " + c);
    EXPECT_EQ(r.exit_code, 0) << c << "\n" << r.err;
  }
  for (const char* f : {"o1.ply", "o2.ply", "o3.ply", "o4.ply", "o6.ply"})
    if (fs::exists(tmp / f)) EXPECT_TRUE(all_finite(read_mesh(tmp / f))) << f;
}

// ---- non-disk input to parametrization --------------------------------------------------------

TEST(BadInputCatalogue, ParamRefusesAnythingButOneDisk) {
  TempDir tmp;
  ASSERT_EQ(run_cli("-q generate sphere --level 0 -o " + (tmp / "sphere.ply")).exit_code, 0);
  ASSERT_EQ(run_cli("-q generate torus --level 0 -o " + (tmp / "torus.ply")).exit_code, 0);
  ASSERT_EQ(run_cli("-q generate cylinder --level 0 -o " + (tmp / "cyl.ply")).exit_code, 0);
  const auto cyl = info_json(tmp / "cyl.ply");
  EXPECT_TRUE(one_line_error(run_cli("param " + (tmp / "sphere.ply") + " -o " + (tmp / "uv.obj")), "closed"));
  EXPECT_TRUE(one_line_error(run_cli("param " + (tmp / "torus.ply") + " -o " + (tmp / "uv.obj")), "closed"));
  // An annulus: two rings of 16 vertices (radii 1 and 2) joined by a band of triangles.
  const int n = 16;
  MatrixX3d V(2 * n, 3);
  MatrixX3i F(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    V.row(i) << std::cos(t), std::sin(t), 0;
    V.row(n + i) << 2 * std::cos(t), 2 * std::sin(t), 0;
    const int j = (i + 1) % n;
    F.row(2 * i) << i, n + i, n + j;
    F.row(2 * i + 1) << i, n + j, j;
  }
  const Mesh annulus = make_mesh(V, F);
  ASSERT_EQ(boundary_loops(annulus).size(), 2u);
  write_mesh(annulus, tmp / "annulus.obj");
  EXPECT_TRUE(one_line_error(run_cli("param " + (tmp / "annulus.obj") + " -o " + (tmp / "uv.obj")), "boundary loops"));
  if (cyl["boundary_loops"].get<int>() == 2)
    EXPECT_TRUE(one_line_error(run_cli("param " + (tmp / "cyl.ply") + " -o " + (tmp / "uv.obj")), "boundary loops"));
  EXPECT_FALSE(fs::exists(tmp / "uv.obj"));
}

// ---- zero-area triangles in the cotangent weights ---------------------------------------------

TEST(BadInputCatalogue, ZeroAreaFacesKeepTheLaplacianFinite) {
  TempDir tmp;
  // A sphere with (a) a collinear triangle pair and (b) two vertices moved onto one point.
  Mesh m = icosphere(2);
  MatrixX3d V = positions(m);
  const MatrixX3i F = faces(m);
  V.row(F(0, 2)) = 0.5 * (V.row(F(0, 0)) + V.row(F(0, 1)));  // corner 2 on the opposite edge: 180°
  V.row(F(50, 1)) = V.row(F(50, 0));                         // two corners at one point
  set_positions(m, V);
  const Eigen::VectorXd areas = face_areas(m);
  ASSERT_GE((areas.array() < 1e-15).count(), 2);
  const SparseMatrix C = cotan_matrix(m);
  for (int k = 0; k < C.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(C, k); it; ++it) ASSERT_TRUE(std::isfinite(it.value()));
  EXPECT_LT((C * Eigen::VectorXd::Ones(C.cols())).cwiseAbs().maxCoeff(), 1e-6);  // rows still sum to 0
  const Eigen::VectorXd mass = mass_diagonal(m);
  EXPECT_TRUE(mass.allFinite());
  EXPECT_GT(mass.minCoeff(), 0);
  for (MassType t : {MassType::Voronoi, MassType::Barycentric, MassType::Thesis}) {
    const SparseMatrix L = cotan_laplacian(m, t);
    for (int k = 0; k < L.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(L, k); it; ++it) ASSERT_TRUE(std::isfinite(it.value()));
  }
  // geotex smooth on it: finite output, explicit and implicit.
  write_mesh(m, tmp / "z.ply");
  for (const std::string opts : {"", " --explicit --lambda 0.1", " --freeze-weights --steps 3", " --mass thesis"}) {
    const CliResult r = run_cli("-q smooth " + (tmp / "z.ply") + " -o " + (tmp / "s.ply") + opts);
    ASSERT_EQ(r.exit_code, 0) << opts << "\n" << r.err;
    EXPECT_TRUE(all_finite(read_mesh(tmp / "s.ply"))) << opts;
  }
}

// ---- a mesh of 10^7 faces ---------------------------------------------------------------------

// A closed torus grid of nu x nv quads (2 nu nv triangles), written straight to binary PLY with float
// coordinates: much faster than building it as a halfedge mesh first.
static void write_torus_ply(const std::string& path, int nu, int nv) {
  std::string s = fmt::format(
      "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
      "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      size_t(nu) * nv, 2 * size_t(nu) * nv);
  const size_t head = s.size();
  s.resize(head + size_t(nu) * nv * 12 + 2 * size_t(nu) * nv * 13);
  char* p = s.data() + head;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      const float xyz[3] = {float((1 + 0.35 * std::cos(v)) * std::cos(u)), float((1 + 0.35 * std::cos(v)) * std::sin(u)),
                            float(0.35 * std::sin(v))};
      std::memcpy(p, xyz, 12);
      p += 12;
    }
  auto id = [&](int i, int j) { return int32_t((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int32_t t[2][3] = {{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, {id(i, j), id(i + 1, j + 1), id(i, j + 1)}};
      for (const auto& tri : t) {
        *p++ = 3;
        std::memcpy(p, tri, 12);
        p += 12;
      }
    }
  write_file(path, s);
}

// `--stats` prints wall time, CPU time and peak memory on every exit path. A torus of 12.6 million
// faces is read by `info`, which reports its peak memory (measured: 2.4 GiB). Heavier commands at this
// size take longer than a test should (see docs/bad-input.md for measured generate and smooth runs).
TEST(BadInputCatalogue, TenMillionFacesAreReadWithinSixGiB) {
  // Sanitizer builds run several times slower and larger: the same checks at 10^6 faces.
  const bool small = test::kAddressSanitizer;
  const int nu = small ? 1024 : 4096, nv = small ? 512 : 1536;
  const long min_kib = (small ? 50L : 500L) * 1024;
  TempDir tmp;
  const std::string big = tmp / "big.ply";
  write_torus_ply(big, nu, nv);
  CliResult r = run_cli("--stats info --json " + big);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["faces"].get<size_t>(), 2u * nu * nv);
  EXPECT_EQ(j["genus"].get<int>(), 1);
  EXPECT_TRUE(j["manifold"].get<bool>());
  // The stats line: "geotex: stats: ... peak memory 2.37 GiB (2479960 KiB)".
  const auto at = r.err.find("peak memory");
  ASSERT_NE(at, std::string::npos) << r.err;
  const auto open = r.err.find('(', at);
  ASSERT_NE(open, std::string::npos) << r.err;
  const long kib = std::stol(r.err.substr(open + 1));
  EXPECT_GT(kib, min_kib);            // a mesh this size takes hundreds of MiB...
  EXPECT_LT(kib, 6L * 1024 * 1024);  // ...and stays within 6 GiB
  // Errors print the stats too, after the one error line.
  write_file(tmp / "bad.obj", "v 0 0 zero\n");
  r = run_cli("--stats info " + (tmp / "bad.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.find("geotex: file error"), 0u) << r.err;
  EXPECT_NE(r.err.find("peak memory"), std::string::npos) << r.err;
  // Without --stats nothing extra is printed.
  EXPECT_EQ(run_cli("-q info " + (tmp / "bad.obj")).err.find("stats"), std::string::npos);
}

// ---- encodings: byte order mark, CRLF and lone CR (issue 14, class 5) ---------------------------

namespace {

std::string with_line_ends(const std::string& lf, const std::string& eol) {
  std::string out;
  for (char c : lf) {
    if (c == '\n') out += eol;
    else out += c;
  }
  return out;
}

// Runs the CLI under a hard time limit (coreutils' timeout): a hang is a failure, not a stuck test.
CliResult run_cli_limited(const std::string& args, int seconds = 30) {
  TempDir tmp;
  const std::string out = tmp / "out.txt", err = tmp / "err.txt";
  const std::string cmd = "timeout -s KILL " + std::to_string(seconds) + " " + std::string(::geotex::test::cli_path()) + " " + args +
                          " >" + out + " 2>" + err + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;  // 137: killed after the time limit
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

}  // namespace

TEST(BadInputCatalogue, ByteOrderMarkAndLineEnds) {
  // On main an OBJ with a BOM lost its first vertex and a lone CR merged every line into one,
  // even with --strict.
  TempDir tmp;
  const Mesh m = icosphere(1);
  for (const char* ext : kFormats) {
    WriteOptions w;
    w.binary = false;
    write_mesh(m, tmp / (std::string("lf.") + ext), w);
    const std::string lf = read_file(tmp / (std::string("lf.") + ext));
    for (const std::string eol : {"\r\n", "\r"})
      for (bool bom : {false, true}) {
        const std::string f = tmp / fmt::format("{}{}.{}", bom ? "bom-" : "", eol.size() == 2 ? "crlf" : "cr", ext);
        write_file(f, (bom ? "\xEF\xBB\xBF" : "") + with_line_ends(lf, eol));
        const CliResult r = run_cli("-q info --strict --json " + f);
        ASSERT_EQ(r.exit_code, 0) << f << ": " << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["vertices"].get<size_t>(), m.n_vertices()) << f;
        EXPECT_EQ(j["faces"].get<size_t>(), m.n_faces()) << f;
      }
  }
}

// ---- PLY declarations and non-integer indices (issue 14, class 5) -------------------------------

TEST(BadInputCatalogue, PlyDuplicatePropertiesAndNonIntegerIndices) {
  TempDir tmp;
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n";
  const std::string rows = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  struct Case {
    const char* name;
    std::string text;
    const char* needle;
  };
  const std::vector<Case> cases = {
      {"x-twice", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                  "0 9 0 0\n1 9 0 0\n0 9 1 0\n3 0 1 2\n", "declared twice"},
      {"fraction-int", head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + rows + "3 0 1.5 2\n",
       "not an integer"},
      {"fraction-float", head + "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + rows + "3 0 1 2.5\n",
       "not an integer index"},
      {"huge", head + "element face 1\nproperty list uchar double vertex_indices\nend_header\n" + rows + "3 0 1 1e300\n",
       "not an integer index"},
      {"nan", head + "element face 1\nproperty list uchar double vertex_indices\nend_header\n" + rows + "3 0 1 nan\n",
       "not an integer index"},
      {"count", head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + rows + "3.5 0 1 2\n",
       "bad list length"},
  };
  for (const auto& c : cases) {
    const std::string f = tmp / (std::string(c.name) + ".ply");
    write_file(f, c.text);
    EXPECT_TRUE(one_line_error(run_cli("info " + f), c.needle)) << c.name;
    EXPECT_TRUE(one_line_error(run_cli("smooth " + f + " -o " + (tmp / "out.ply")), c.needle)) << c.name;
    EXPECT_FALSE(fs::exists(tmp / "out.ply"));
  }
}

// ---- special files as inputs (issue 14, class 7) --------------------------------------------------

TEST(BadInputCatalogue, FifosAndDevicesAreRefusedAtOnce) {
  // On main a FIFO input blocked forever and /dev/zero as a handles or feature file was read until
  // memory ran out. Now: one line at once.
  TempDir tmp;
  const std::string cube = tmp / "cube.obj";
  ASSERT_EQ(run_cli("-q generate cube --level 0 -o " + cube).exit_code, 0);
  ASSERT_EQ(::mkfifo((tmp / "fifo.obj").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((tmp / "fifo.json").c_str(), 0644), 0);
  fs::create_symlink("/dev/zero", tmp.path / "zero.json");
  fs::create_symlink("/dev/zero", tmp.path / "zero.txt");
  const std::string out = tmp / "out.obj";
  EXPECT_TRUE(one_line_error(run_cli_limited("info " + (tmp / "fifo.obj")), "FIFO"));
  EXPECT_TRUE(one_line_error(run_cli_limited("smooth " + (tmp / "fifo.obj") + " -o " + out), "FIFO"));
  EXPECT_TRUE(one_line_error(run_cli_limited("deform " + cube + " --handles " + (tmp / "fifo.json") + " -o " + out), "FIFO"));
  EXPECT_TRUE(one_line_error(run_cli_limited("deform " + cube + " --handles " + (tmp / "zero.json") + " -o " + out), "device"));
  EXPECT_TRUE(one_line_error(run_cli_limited("resize " + cube + " --scale 2,1,1 --features " + (tmp / "zero.txt") + " -o " + out),
                             "device"));
  EXPECT_TRUE(one_line_error(run_cli_limited("surfels " + (tmp / "zero.txt") + " -o " + (tmp / "s.ply")), "device"));
  // texture synthesize --weight had a reader of its own that waited on a FIFO (found by hand, 2026-12-02);
  // it reads feature files now: regular files only, one weight in [0, 1] per line.
  const std::string texture = tmp / "t.ply";
  ASSERT_EQ(run_cli("-q texture extract " + cube + " -o " + texture).exit_code, 0);
  const std::string synth = "texture synthesize " + texture + " --target " + cube + " --candidates 4 -o " + out;
  EXPECT_TRUE(one_line_error(run_cli_limited(synth + " --weight " + (tmp / "fifo.obj")), "FIFO"));
  EXPECT_TRUE(one_line_error(run_cli_limited(synth + " --weight " + (tmp / "zero.txt")), "device"));
  write_file(tmp / "w.txt", "0.5\n2\n");
  EXPECT_TRUE(one_line_error(run_cli_limited(synth + " --weight " + (tmp / "w.txt")), "2 feature weights for 152 vertices"));
  EXPECT_FALSE(fs::exists(out));
  std::string weights;
  for (int i = 0; i < 152; ++i) weights += i < 76 ? "1\n" : "0\n";
  write_file(tmp / "w.txt", weights);
  EXPECT_EQ(run_cli_limited("-q " + synth + " --weight " + (tmp / "w.txt")).exit_code, 0);
  EXPECT_TRUE(fs::exists(out));
}

// ---- the output path (issue 14, class 3) ----------------------------------------------------------

TEST(BadInputCatalogue, OutputPathIsKeptAsTheUserMadeIt) {
  TempDir tmp;
  const std::string cube = "-q generate cube --level 0 -o ";
  // A FIFO or a device at the output path is refused without blocking (main replaced it by a file,
  // or waited for a reader).
  ASSERT_EQ(::mkfifo((tmp / "fifo.obj").c_str(), 0644), 0);
  EXPECT_TRUE(one_line_error(run_cli_limited(cube + (tmp / "fifo.obj")), "FIFO"));
  EXPECT_TRUE(fs::is_fifo(tmp.path / "fifo.obj"));
  // A read-only file is not replaced.
  write_file(tmp / "ro.obj", "keep me");
  ::chmod((tmp / "ro.obj").c_str(), 0444);
  EXPECT_TRUE(one_line_error(run_cli(cube + (tmp / "ro.obj")), "is read-only; geotex does not replace it"));
  EXPECT_EQ(read_file(tmp / "ro.obj"), "keep me");
  // A replaced file keeps its mode.
  write_file(tmp / "private.obj", "old");
  ::chmod((tmp / "private.obj").c_str(), 0600);
  ASSERT_EQ(run_cli(cube + (tmp / "private.obj")).exit_code, 0);
  struct stat st {};
  ASSERT_EQ(::stat((tmp / "private.obj").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  // A symbolic link stays a link; its target gets the result.
  fs::create_symlink("private.obj", tmp.path / "link.obj");
  write_file(tmp / "private.obj", "old");
  ASSERT_EQ(run_cli(cube + (tmp / "link.obj")).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(tmp.path / "link.obj"));
  EXPECT_NE(read_file(tmp / "private.obj"), "old");
  // A name of 250 characters works (main's temporary name was 13 characters longer than the name).
  const std::string long_name = tmp / (std::string(246, 'n') + ".obj");
  ASSERT_EQ(run_cli(cube + long_name).exit_code, 0);
  EXPECT_GT(info_json(long_name)["faces"].get<size_t>(), 0u);
  // No temporary is left anywhere.
  for (const auto& e : fs::directory_iterator(tmp.path)) EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

TEST(BadInputCatalogue, NonFiniteResultsAreNotWritten) {
  // Coordinates of 1e200 are finite, but noise and denoise overflowed on them: on main the inf/NaN
  // result was written with exit 0 (a file geotex's own reader refuses). Every method now refuses
  // coordinates beyond kMaxCoordinate up front (the writers also refuse non-finite output).
  TempDir tmp;
  write_file(tmp / "big.obj", "v 0 0 0\nv 1e200 0 0\nv 0 1e200 0\nv 0 0 1e200\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  for (const std::string cmd : {"noise", "denoise --method mrf", "denoise", "smooth"}) {
    write_file(tmp / "out.obj", "old");
    const CliResult r = run_cli("-q " + cmd + " " + (tmp / "big.obj") + " -o " + (tmp / "out.obj"));
    EXPECT_TRUE(one_line_error(r, "coordinates reach 1e+200")) << cmd;
    EXPECT_TRUE(one_line_error(r, "scale the mesh down")) << cmd;
    EXPECT_EQ(read_file(tmp / "out.obj"), "old") << cmd;
  }
}

TEST(BadInputCatalogue, CoordinatesOutsideTheComputableRangeAreRefused) {
  // A unit sphere scaled by 1e150 or 1e-150 reads fine, but fourth powers of its lengths (squared
  // areas, inverse squared lengths in the 1-form fit) leave double precision: texture animate and
  // resize failed with "sparse Cholesky failed (not positive definite?)". Now every command that
  // computes says which way to rescale; at the edges of the range (1e74, 1e-74) they all compute.
  TempDir tmp;
  const Mesh sphere = icosphere(2);
  const std::vector<std::string> cmds = {"smooth", "denoise", "resize --scale 2,1,1", "texture extract",
                                         "render"};
  for (const auto& [scale, advice] : std::vector<std::pair<double, std::string>>{
           {1e150, "scale the mesh down"}, {1e-150, "scale the mesh up"}, {1e74, ""}, {1e-74, ""}}) {
    Mesh scaled = sphere;
    set_positions(scaled, positions(sphere) * scale);
    const fs::path in = tmp / "scaled.ply";
    write_mesh(scaled, in);
    for (const auto& cmd : cmds) {
      const fs::path out = tmp / (cmd.rfind("render", 0) == 0 ? "out.png" : cmd.rfind("texture", 0) == 0 ? "t.ply" : "out.ply");
      fs::remove(out);
      const CliResult r = run_cli("-q " + cmd + " " + in.string() + " -o " + out.string());
      if (advice.empty()) {
        EXPECT_EQ(r.exit_code, 0) << cmd << " at " << scale << ": " << r.err;
        if (out.extension() == ".ply") EXPECT_TRUE(all_finite(read_mesh(out))) << cmd << " at " << scale;
      } else {
        EXPECT_TRUE(one_line_error(r, advice)) << cmd << " at " << scale << ": " << r.err;
        EXPECT_FALSE(fs::exists(out)) << cmd << " at " << scale;
      }
    }
  }
}
