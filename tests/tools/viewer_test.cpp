// Viewer pages: the embedded data decodes back to the mesh (within the stated quantisation bound),
// layers are read from PLY files, edge files are bound to their meshes, bad inputs fail clearly, and
// (when Debian's chromium, node and viewer/node_modules are present) the page loads in headless
// Chromium without console errors, shows every mesh at one scale and draws labels on off-centre
// meshes (viewer/test/viewer_check.mjs).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/tools/shapes.h"
#include "geotex/tools/viewer.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::run_cli;
using geotex::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::string unbase64(const std::string& s) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::string out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    const int v = val(c);
    if (v < 0) break;  // '=' padding
    acc = (acc << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

// A page array: base64 of a zlib stream (inflated here by zlib, independently of the browser's).
std::string inflate(const std::string& b64) {
  const std::string z = unbase64(b64);
  std::string out(std::max<size_t>(64, 8 * z.size()), '\0');
  for (;;) {
    uLongf size = out.size();
    const int rc = uncompress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(z.data()), z.size());
    if (rc == Z_BUF_ERROR) {
      out.resize(2 * out.size());
      continue;
    }
    EXPECT_EQ(rc, Z_OK);
    out.resize(size);
    return out;
  }
}

std::vector<uint32_t> varints(const std::string& bytes) {
  std::vector<uint32_t> out;
  uint32_t v = 0;
  int shift = 0;
  for (unsigned char b : bytes) {
    v |= uint32_t(b & 0x7F) << shift;
    shift += 7;
    if (!(b & 0x80)) out.push_back(v), v = 0, shift = 0;
  }
  EXPECT_EQ(shift, 0) << "truncated varint";
  return out;
}

// Codes of block `block` of byte planes of deltas (low byte first).
std::vector<uint32_t> plane_codes(const std::string& bytes, size_t n, int planes, int block) {
  std::vector<uint32_t> q(n);
  const uint64_t mod = uint64_t(1) << (8 * planes);
  uint64_t acc = 0;
  for (size_t i = 0; i < n; ++i) {
    uint64_t d = 0;
    for (int k = 0; k < planes; ++k) d |= uint64_t(uint8_t(bytes.at((block * planes + k) * n + i))) << (8 * k);
    acc = (acc + d) % mod;
    q[i] = static_cast<uint32_t>(acc);
  }
  return q;
}

// A mesh as a page holds it, in file coordinates, in the page's vertex and face order.
struct Decoded {
  MatrixX3d V;
  MatrixX3i F;
  std::map<std::string, Eigen::VectorXd> fields;
  MatrixX2i edges;
  std::vector<uint32_t> labels;
};

Decoded decode_mesh(const nlohmann::json& j) {
  Decoded d;
  const size_t n = j["vertices"], nf = j["faces"];
  const auto& p = j["positions"];
  const std::string pos = inflate(p["data"]);
  EXPECT_EQ(pos.size(), 3 * n * p["planes"].get<size_t>());
  d.V.resize(n, 3);
  for (int k = 0; k < 3; ++k) {
    const auto q = plane_codes(pos, n, p["planes"], k);
    for (size_t i = 0; i < n; ++i)
      d.V(i, k) = j["origin"][k].get<double>() + p["offset"][k].get<double>() + p["step"][k].get<double>() * q[i];
  }
  const auto codes = varints(inflate(j["indices"]));
  EXPECT_EQ(codes.size(), 3 * nf);
  d.F.resize(nf, 3);
  int64_t next = 0;
  for (size_t i = 0; i < codes.size(); ++i) {
    const int64_t g = next - codes[i];
    EXPECT_GE(g, 0);
    d.F(i / 3, i % 3) = static_cast<int>(g);
    next = std::max(next, g + 1);
  }
  for (const auto& [name, f] : j["fields"].items()) {
    const auto q = plane_codes(inflate(f["data"]), n, 2, 0);
    Eigen::VectorXd v(n);
    for (size_t i = 0; i < n; ++i)
      v[i] = q[i] == 65535 ? std::nan("") : f["lo"].get<double>() + f["step"].get<double>() * q[i];
    d.fields[name] = v;
  }
  if (j.contains("edges")) {
    const auto z = varints(inflate(j["edges"]["pairs"]));
    d.edges.resize(z.size() / 2, 2);
    int64_t prev = 0;
    for (size_t i = 0; i < z.size(); ++i) {
      prev += (z[i] & 1) ? -static_cast<int64_t>((z[i] + 1) / 2) : static_cast<int64_t>(z[i] / 2);
      d.edges(i / 2, i % 2) = static_cast<int>(prev);
    }
    d.labels = varints(inflate(j["edges"]["labels"]));
  }
  return d;
}

// The page's vertex for each mesh vertex (the nearest decoded position; meshes in tests have well
// separated vertices), checking that each lies within \p bound per axis.
std::vector<int> match_vertices(const MatrixX3d& V, const MatrixX3d& W, const Vec3& bound) {
  std::vector<int> page_of(V.rows(), -1);
  std::map<std::tuple<long, long, long>, std::vector<int>> grid;
  const double cell = 1e-3 + 4 * bound.maxCoeff();
  auto key = [&](const Eigen::RowVector3d& p, int dx, int dy, int dz) {
    return std::tuple<long, long, long>(std::lround(std::floor(p[0] / cell)) + dx, std::lround(std::floor(p[1] / cell)) + dy,
                                        std::lround(std::floor(p[2] / cell)) + dz);
  };
  for (Eigen::Index i = 0; i < W.rows(); ++i) grid[key(W.row(i), 0, 0, 0)].push_back(static_cast<int>(i));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    double best = std::numeric_limits<double>::max();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (auto it = grid.find(key(V.row(i), dx, dy, dz)); it != grid.end())
            for (int w : it->second)
              if (const double dist = (W.row(w) - V.row(i)).squaredNorm(); dist < best) best = dist, page_of[i] = w;
    EXPECT_GE(page_of[i], 0) << "vertex " << i << " not on the page";
    if (page_of[i] >= 0)
      for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(W(page_of[i], k) - V(i, k)), bound[k]) << "vertex " << i;
  }
  return page_of;
}

// Triangles as sorted rotations (orientation kept), for comparing face sets in any order.
std::vector<std::array<int, 3>> canonical(const MatrixX3i& F, const std::vector<int>* map = nullptr) {
  std::vector<std::array<int, 3>> t;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    std::array<int, 3> a{F(f, 0), F(f, 1), F(f, 2)};
    if (map)
      for (int& v : a) v = (*map)[v];
    std::rotate(a.begin(), std::min_element(a.begin(), a.end()), a.end());
    t.push_back(a);
  }
  std::sort(t.begin(), t.end());
  return t;
}

nlohmann::json page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"geotex-data\">";
  const size_t a = page.find(open);
  EXPECT_NE(a, std::string::npos);
  const size_t b = page.find("</script>", a);
  return nlohmann::json::parse(page.substr(a + open.size(), b - a - open.size()));
}

bool have_node() { return std::system("node --version >/dev/null 2>&1") == 0; }

}  // namespace

TEST(ViewerPage, EmbeddedDataDecodesToTheMesh) {
  // Off the origin, with a stray vertex: positions stay within the stated bound, faces keep their
  // vertices and orientation, fields and labelled edges follow their vertices.
  const Mesh ball = icosphere(3, 1.5);
  MatrixX3d V0 = positions(ball);
  V0.rowwise() += Eigen::RowVector3d(1000, -500, 250);
  MatrixX3d V(V0.rows() + 1, 3);
  V << V0, Eigen::RowVector3d(1000, -490, 250);
  const Mesh m = make_mesh(V, faces(ball));
  ASSERT_EQ(m.n_vertices(), static_cast<size_t>(V.rows()));
  ViewerMesh vm{"ball </script> & <b>", m, {}};
  vm.layers.fields["height"] = V.col(1);
  vm.layers.fields["height"][5] = std::nan("");
  const MatrixX2i E = edges(m);
  vm.layers.segments = E.topRows(30);
  vm.layers.labels = Eigen::VectorXi::LinSpaced(30, 1, 30);
  ViewerOptions o;
  o.title = "a <title>";
  o.initial_field = "height";
  const std::string page = viewer_page({vm, vm}, o, "window.x = 1;");
  EXPECT_EQ(page.find("<title>a <title>"), std::string::npos);  // escaped
  EXPECT_NE(page.find("a &lt;title&gt;"), std::string::npos);
  EXPECT_NE(page.find("window.x = 1;"), std::string::npos);
  const nlohmann::json d = page_data(page);  // the name's "</script>" did not end the data early
  ASSERT_EQ(d["meshes"].size(), 2u);
  const auto& j = d["meshes"][0];
  EXPECT_EQ(j["name"], "ball </script> & <b>");
  EXPECT_EQ(d["initialField"], "height");
  // The frame ignores the stray vertex: origin at the ball's centre, radius 1.5.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(j["origin"][k].get<double>(), V0.colwise().mean()[k], 1e-9);
  EXPECT_NEAR(j["radius"].get<double>(), 1.5, 1e-9);
  // Auto up: a round ball resting on no plane is y-up.
  EXPECT_EQ(d["up"], nlohmann::json({0.0, 1.0, 0.0}));

  const Decoded got = decode_mesh(j);
  ASSERT_EQ(got.V.rows(), V.rows());
  const Vec3 extent = (V.colwise().maxCoeff() - V.colwise().minCoeff()).transpose();
  const Vec3 bound = extent / (2 * 65535.0) * (1 + 1e-9) + Vec3::Constant(1e-9);  // extent / 2^(bits+1)
  const std::vector<int> page_of = match_vertices(V, got.V, bound);
  EXPECT_EQ(canonical(got.F), canonical(faces(m), &page_of));
  const Eigen::VectorXd& h = got.fields.at("height");
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (i == 5) EXPECT_TRUE(std::isnan(h[page_of[i]]));
    else EXPECT_NEAR(h[page_of[i]], V(i, 1), (V.col(1).maxCoeff() - V.col(1).minCoeff()) / 65534.0);
  }
  ASSERT_EQ(got.edges.rows(), 30);
  for (int e = 0; e < 30; ++e) {
    EXPECT_EQ(got.edges(e, 0), page_of[E(e, 0)]);
    EXPECT_EQ(got.edges(e, 1), page_of[E(e, 1)]);
    EXPECT_EQ(got.labels[e], static_cast<uint32_t>(e + 1));
  }
  // More bits, a smaller error.
  o.position_bits = 24;
  const Decoded fine = decode_mesh(page_data(viewer_page({vm}, o, "x"))["meshes"][0]);
  match_vertices(V, fine.V, extent / (2 * 16777215.0) + Vec3::Constant(1e-9));
  o.position_bits = 30;
  EXPECT_THROW(viewer_page({vm}, o, "x"), InvalidInput);
}

TEST(ViewerPage, PageIsUnderAQuarterOfTheRawArrays) {
  // 20,480 faces: far below the 12 + 12 bytes per vertex and face of raw float32 / uint32 arrays.
  const Mesh m = icosphere(5, 1.0);
  ViewerMesh vm{"m", m, {}};
  const std::string page = viewer_page({vm}, {}, "x");
  const double raw = 12.0 * m.n_vertices() + 12.0 * m.n_faces();
  EXPECT_LT(page.size(), 0.25 * raw) << page.size() << " bytes";
}

//! The 8 corners of the box lo .. hi (as points).
MatrixX3d box_corners(const Vec3& lo, const Vec3& hi) {
  MatrixX3d P(8, 3);
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) P(i, k) = (i >> k) & 1 ? hi[k] : lo[k];
  return P;
}

TEST(ViewerPage, AutoUpFollowsTheBoundingBox) {
  const Vec3 o = Vec3::Zero();
  EXPECT_EQ(up_vector(UpAxis::Auto, box_corners(o, Vec3(2, 2, 0.5))), Vec3::UnitZ());  // flat: the thin axis
  EXPECT_EQ(up_vector(UpAxis::Auto, box_corners(Vec3(-1, -0.1, -1), Vec3(1, 0.1, 1))), Vec3::UnitY());
  EXPECT_EQ(up_vector(UpAxis::Auto, box_corners(Vec3(-3, 0, -2), Vec3(3.4, 3.2, 2))), Vec3::UnitY());  // rests on y = 0
  EXPECT_EQ(up_vector(UpAxis::Auto, box_corners(Vec3(-1, -1, 0), Vec3(1, 1, 1.5))), Vec3::UnitZ());    // rests on z = 0
  EXPECT_EQ(up_vector(UpAxis::Auto, box_corners(Vec3(-1, -1, -1), Vec3(1, 1, 1))), Vec3::UnitY());     // a tie: y
  EXPECT_EQ(up_vector(UpAxis::NegZ, box_corners(o, o)), -Vec3::UnitZ());
  EXPECT_EQ(parse_enum(up_axis_names(), "-x", "up"), UpAxis::NegX);
}

//! A cone standing on its base disk, apex along \p up: the footprint rule must find the disk on
//! whichever axis the cone stands, and y when it could stand on nothing better.
MatrixX3d cone_points(const Vec3& up, const Vec3& offset) {
  const Vec3 a = up.cross(std::abs(up.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized(), b = up.cross(a);
  const int n = 64;
  MatrixX3d P(n + 1, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    P.row(i) = (offset + std::cos(t) * a + std::sin(t) * b).transpose();
  }
  P.row(n) = (offset + 1.5 * up).transpose();
  return P;
}

TEST(ViewerPage, AutoUpIsTheSideTheModelStandsOn) {
  const Vec3 off(0.3, -2.7, 5.1);  // off-centre, so no side rests at 0
  for (const Vec3& up : {Vec3(Vec3::UnitZ()), Vec3(-Vec3::UnitZ()), Vec3(Vec3::UnitX()), Vec3(-Vec3::UnitY()),
                         Vec3(Vec3::UnitY())})
    EXPECT_EQ(up_vector(UpAxis::Auto, cone_points(up, off)), up) << up.transpose();
  // A sphere stands on a point along every axis: y.
  const MatrixX3d S = positions(icosphere(3, 1.0)).rowwise() + off.transpose();
  EXPECT_EQ(up_vector(UpAxis::Auto, S), Vec3::UnitY());
}

TEST(ViewerPage, AutoUpOfRealModelsAsGivenAndTurnedZUp) {
  GEOTEX_REQUIRE_DATA();
  // y-up models as published; turned z-up ((x, y, z) -> (x, -z, y)) the same rule must say z.
  for (const char* name : {"stanford-bunny.obj", "spot.obj", "cow.obj", "beetle.obj", "teapot.obj"}) {
    const MatrixX3d P = face_vertices(read_mesh(test::data_dir() / name));
    EXPECT_EQ(up_vector(UpAxis::Auto, P), Vec3::UnitY()) << name;
    MatrixX3d Q(P.rows(), 3);
    Q << P.col(0), -P.col(2), P.col(1);
    EXPECT_EQ(up_vector(UpAxis::Auto, Q), Vec3::UnitZ()) << name << " turned z-up";
  }
}

TEST(ViewerPage, WrongSizedLayersOrNoMeshThrow) {
  const Mesh m = icosphere(1, 1.0);
  ViewerMesh vm{"m", m, {}};
  vm.layers.fields["short"] = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(viewer_page({vm}, {}, "x"), InvalidInput);
  ViewerMesh ve{"m", m, {}};
  ve.layers.segments.resize(1, 2);
  ve.layers.segments << 0, 99999;
  EXPECT_THROW(viewer_page({ve}, {}, "x"), InvalidInput);
  EXPECT_THROW(viewer_page({}, {}, "x"), InvalidInput);
}

TEST(ViewerLayers, PlyVertexPropertiesBecomeLayers) {
  TempDir dir;
  const Mesh m = icosphere(1, 1.0);
  const MatrixX3d V = positions(m);
  PlyExtras x;
  x.vertex_scalars["height"] = std::vector<double>(V.col(2).data(), V.col(2).data() + V.rows());
  write_ply(m, dir / "m.ply", x);
  const MeshLayers l = read_mesh_layers(dir / "m.ply", m.n_vertices());
  ASSERT_EQ(l.fields.size(), 1u);
  EXPECT_TRUE(l.fields.at("height").isApprox(V.col(2)));
  EXPECT_EQ(l.segments.rows(), 0);
  // Edge labels: only edges labelled above 0.5 become segments, with their label.
  Eigen::VectorXd labels = Eigen::VectorXd::Zero(m.n_edges());
  labels[3] = 1;
  labels[7] = 2;
  write_edge_values(m, labels, "label", dir / "e.ply");
  const MeshLayers e = read_mesh_layers(dir / "e.ply", m.n_vertices());
  ASSERT_EQ(e.segments.rows(), 2);
  const MatrixX2i E = edges(m);
  EXPECT_EQ(e.segments.row(0), E.row(3));
  EXPECT_EQ(e.segments.row(1), E.row(7));
  EXPECT_EQ(e.labels[1], 2);
  MeshLayers again;
  read_edge_labels(dir / "e.ply", m.n_vertices(), again);
  EXPECT_EQ(again.segments, e.segments);
  EXPECT_THROW(read_edge_labels(dir / "e.ply", 5, again), InvalidInput);  // indices beyond the mesh
  EXPECT_THROW(read_edge_labels(dir / "m.ply", m.n_vertices(), again), IoError);  // no edge element
}

TEST(ViewerLayers, FieldFileGivesOneNumberPerVertex) {
  TempDir dir;
  geotex::test::write_file(dir / "f.txt", "1 2.5\n-3,4e-2\n");
  const Eigen::VectorXd f = read_field_file(dir / "f.txt", 4);
  EXPECT_EQ(f, Eigen::Vector4d(1, 2.5, -3, 0.04));
  EXPECT_THROW(read_field_file(dir / "f.txt", 5), InvalidInput);
  geotex::test::write_file(dir / "g.txt", "1 two 3");
  EXPECT_THROW(read_field_file(dir / "g.txt", 3), IoError);
  EXPECT_THROW(read_field_file(dir / "none.txt", 3), IoError);
}

TEST(ViewCli, BadArgumentsFailWithOneLine) {
  TempDir dir;
  write_mesh(icosphere(1, 1.0), dir / "s.ply");
  for (const std::string& args : std::vector<std::string>{
           dir / "s.ply" + " -o " + dir / "p.txt", dir / "missing.ply" + " -o " + dir / "p.html",
           dir / "s.ply" + " -o " + dir / "p.html --field nosuch",
           dir / "s.ply" + " -o " + dir / "p.html --field-file " + dir / "s.ply"}) {
    const auto r = run_cli("view " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_FALSE(r.err.empty()) << args;
    EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << args << ": " << r.err;
  }
  const auto h = run_cli("view --help");
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("--reference"), std::string::npos);
  // Without a viewer bundle the command says so in one line.
  ::setenv("GEOTEX_VIEWER_JS", (dir / "nosuch.js").c_str(), 1);
  const auto r = run_cli("view " + dir / "s.ply" + " -o " + dir / "p.html");
  ::unsetenv("GEOTEX_VIEWER_JS");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("GEOTEX_VIEWER_JS"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "p.html"));
}

bool have_viewer_script() {
  try {
    viewer_script();
    return true;
  } catch (const IoError&) {
    return false;
  }
}

TEST(ViewCli, WritesAPageWithTheFieldsAndLabels) {
  if (!have_viewer_script()) GTEST_SKIP() << "the viewer's script was not built (scripts/setup_viewer.sh)";
  TempDir dir;
  const Mesh m = icosphere(2, 1.0);
  Eigen::VectorXd labels = Eigen::VectorXd::Zero(m.n_edges());
  labels.head(20).setOnes();
  write_edge_values(m, labels, "label", dir / "e.ply");
  write_mesh(m, dir / "a.ply");
  write_mesh(icosphere(3, 1.05), dir / "b.ply");
  const auto r = run_cli("view " + dir / "a.ply" + " " + dir / "b.ply" + " -o " + dir / "p.html --reference " +
                         dir / "b.ply" + " --edges a.ply:" + dir / "e.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json d = page_data(geotex::test::read_file(dir / "p.html"));
  ASSERT_EQ(d["meshes"].size(), 2u);
  EXPECT_EQ(d["initialField"], "error");
  const Decoded a = decode_mesh(d["meshes"][0]);
  ASSERT_EQ(a.fields.at("error").size(), static_cast<Eigen::Index>(m.n_vertices()));
  for (double e : a.fields.at("error")) EXPECT_NEAR(e, 0.05, 0.01);  // radius 1 against radius 1.05
  EXPECT_EQ(a.edges.rows(), 20);
  EXPECT_FALSE(d["meshes"][1].contains("edges"));
}

TEST(ViewCli, EdgeAndFieldFilesAreBoundToTheirMeshes) {
  if (!have_viewer_script()) GTEST_SKIP() << "the viewer's script was not built (scripts/setup_viewer.sh)";
  TempDir dir;
  const Mesh m = icosphere(1, 1.0);
  fs::create_directories(dir / "x");
  for (const char* f : {"a.ply", "b.ply", "c.ply", "x/a.ply"}) write_mesh(m, dir / f);
  Eigen::VectorXd labels = Eigen::VectorXd::Zero(m.n_edges());
  labels.head(7).setOnes();
  write_edge_values(m, labels, "label", dir / "e.ply");
  labels.head(9).setOnes();
  write_edge_values(m, labels, "label", dir / "f.ply");
  std::string values;
  for (size_t i = 0; i < m.n_vertices(); ++i) values += fmt::format("{} ", i);
  geotex::test::write_file(dir / "v.txt", values);
  const std::string abc = dir / "a.ply" + " " + dir / "b.ply" + " " + dir / "c.ply" + " -o " + dir / "p.html";
  auto edge_counts = [&] {
    std::vector<long> n;
    const nlohmann::json d = page_data(geotex::test::read_file(dir / "p.html"));
    for (const auto& j : d["meshes"])
      n.push_back(j.contains("edges") ? j["edges"]["count"].get<long>() : 0);
    return n;
  };
  // By position and by file name, in any order.
  auto r = run_cli("view " + abc + " --edges 3:" + dir / "e.ply" + " --edges b.ply:" + dir / "f.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(edge_counts(), (std::vector<long>{0, 9, 7}));
  // By the path as given.
  r = run_cli("view " + abc + " --edges " + dir / "a.ply" + ":" + dir / "e.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(edge_counts(), (std::vector<long>{7, 0, 0}));
  // One mesh: no binding needed.
  r = run_cli("view " + dir / "b.ply" + " -o " + dir / "p.html --edges " + dir / "f.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(edge_counts(), (std::vector<long>{9}));
  // A field file for mesh 2 only: the others show the same field name without values.
  r = run_cli("view " + abc + " --field-file 2:" + dir / "v.txt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json d = page_data(geotex::test::read_file(dir / "p.html"));
  EXPECT_EQ(d["initialField"], "file");
  EXPECT_FALSE(d["meshes"][0]["fields"].contains("file"));
  EXPECT_TRUE(d["meshes"][1]["fields"].contains("file"));

  // Errors, each in one line, and no page.
  const std::string e = dir / "e.ply";
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {abc + " --edges " + e, "say which mesh"},                                      // unbound, 3 meshes
           {abc + " --edges 4:" + e, "no mesh 4"},                                        // no such position
           {abc + " --edges 0:" + e, "no mesh 0"},
           {abc + " --edges d.ply:" + e, "say which mesh"},                               // no such name
           {abc + " --edges 1:" + e + " --edges a.ply:" + e, "two files"},               // twice for mesh 1
           {abc + " --edges 2:" + dir / "none.ply", "no such file"},
           {abc + " --edges 2:", "no file"},
           {abc + " " + dir / "x/a.ply" + " --edges a.ply:" + e, "names meshes 1 and 4"},  // ambiguous name
           {abc + " --field-file " + dir / "v.txt", "say which mesh"},
           {abc + " --field nosuch", "no mesh has"}}) {
    fs::remove(dir / "p.html");
    const auto bad = run_cli("view " + args);
    EXPECT_NE(bad.exit_code, 0) << args;
    EXPECT_NE(bad.err.find(says), std::string::npos) << args << ": " << bad.err;
    EXPECT_LE(std::count(bad.err.begin(), bad.err.end(), '\n'), 2) << args << ": " << bad.err;
    EXPECT_FALSE(fs::exists(dir / "p.html")) << args;
  }
}

// The pages in Debian's headless Chromium (Playwright from npm drives /usr/bin/chromium).
TEST(ViewerChromium, OffCentreMeshesShowTheirLabelsOnThemAtOneScale) {
  const fs::path viewer = fs::path(::geotex::test::source_dir()) / "viewer";
  if (!fs::exists("/usr/bin/chromium")) GTEST_SKIP() << "/usr/bin/chromium not found (scripts/setup_viewer.sh installs it)";
  if (!have_node()) GTEST_SKIP() << "node not found (scripts/setup_viewer.sh installs it)";
  if (!fs::exists(viewer / "node_modules" / "playwright-core"))
    GTEST_SKIP() << "viewer/node_modules/playwright-core missing (run scripts/setup_viewer.sh)";
  if (!have_viewer_script()) GTEST_SKIP() << "the viewer's script was not built (scripts/setup_viewer.sh)";
  TempDir dir;
  // A y-up ball far from the origin, with its equator (y = 0 before the move) labelled, and a copy
  // twice as large elsewhere, coloured by height: labels must sit on each ball, the second twice as tall.
  const Mesh ball = icosphere(4, 1.0);
  const MatrixX3d B = positions(ball);
  Mesh near = ball, far = ball;
  set_positions(near, B.rowwise() + Eigen::RowVector3d(1000, -500, 250));
  set_positions(far, (2 * B).rowwise() + Eigen::RowVector3d(-300, 40, 7));
  PlyExtras x;
  const MatrixX3d F = positions(far);
  x.vertex_scalars["height"] = std::vector<double>(F.col(1).data(), F.col(1).data() + F.rows());
  write_mesh(near, dir / "near.ply");
  write_ply(far, dir / "far.ply", x);
  // The equator: edges between a face above y = 0 and one below (a closed zig-zag loop).
  Eigen::VectorXd ring = Eigen::VectorXd::Zero(ball.n_edges());
  auto above = [&](Mesh::FaceHandle f) {
    double y = 0;
    for (auto v : ball.fv_range(f)) y += B(v.idx(), 1);
    return y > 0;
  };
  for (auto e : ball.edges())
    ring[e.idx()] = above(ball.face_handle(e.halfedge(0))) != above(ball.face_handle(e.halfedge(1))) ? 1.0 : 0.0;
  ASSERT_GT(ring.sum(), 60);
  write_edge_values(ball, ring, "label", dir / "ring.ply");
  const auto r = run_cli("view " + dir / "near.ply" + " " + dir / "far.ply" + " -o " + dir / "page.html" +
                         " --edges near.ply:" + dir / "ring.ply" + " --edges 2:" + dir / "ring.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The screenshot stays in the build folder for people to look at.
  const fs::path shots = fs::current_path() / "viewer-screenshots";
  fs::create_directories(shots);
  const std::string log = dir / "check.log";
  const std::string cmd = "cd " + viewer.string() + " && node test/viewer_check.mjs " + dir / "page.html" + " " +
                          (shots / "off-centre.png").string() + " 2 --labels-on-mesh --size-ratio 2 >" + log + " 2>&1";
  const int status = std::system(cmd.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  const std::string out = geotex::test::read_file(log);
  if (code == 77) GTEST_SKIP() << out;
  EXPECT_EQ(code, 0) << out;
  EXPECT_TRUE(fs::exists(shots / "off-centre.png"));
  std::printf("%s", out.c_str());
}
