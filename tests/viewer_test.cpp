// Viewer pages: the embedded data decodes back to the mesh, layers are read from PLY files, bad
// inputs fail clearly, and (when Debian's chromium, node and viewer/node_modules are present) the page
// loads in headless Chromium without console errors and shows every mesh (viewer/test/viewer_check.mjs).

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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

template <class T>
std::vector<T> decode(const std::string& b64) {
  const std::string bytes = unbase64(b64);
  EXPECT_EQ(bytes.size() % sizeof(T), 0u);
  std::vector<T> v(bytes.size() / sizeof(T));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
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
  const Mesh m = icosphere(2, 1.5);
  ViewerMesh vm{"ball </script> & <b>", m, {}};
  vm.layers.fields["height"] = positions(m).col(2);
  vm.layers.segments.resize(2, 2);
  vm.layers.segments << 0, 1, 1, 2;
  vm.layers.labels.resize(2);
  vm.layers.labels << 1, 3;
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
  const MatrixX3d V = positions(m);
  const MatrixX3i F = faces(m);
  const auto p = decode<float>(j["positions"]);
  const auto f = decode<uint32_t>(j["indices"]);
  const auto h = decode<float>(j["fields"]["height"]);
  ASSERT_EQ(p.size(), static_cast<size_t>(V.size()));
  ASSERT_EQ(f.size(), static_cast<size_t>(F.size()));
  ASSERT_EQ(h.size(), static_cast<size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(p[3 * i + k], static_cast<float>(V(i, k)));
    EXPECT_EQ(h[i], static_cast<float>(V(i, 2)));
  }
  for (Eigen::Index i = 0; i < F.rows(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(f[3 * i + k], static_cast<uint32_t>(F(i, k)));
  EXPECT_EQ(decode<uint32_t>(j["edges"]), (std::vector<uint32_t>{0, 1, 1, 2}));
  EXPECT_EQ(decode<int32_t>(j["edgeLabels"]), (std::vector<int32_t>{1, 3}));
}

TEST(ViewerPage, BadLayersThrow) {
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

TEST(ViewerLayers, ReadFromPly) {
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

TEST(ViewerLayers, FieldFile) {
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

TEST(ViewCli, WritesAPageWithTheFieldsAndLabels) {
  try {
    viewer_script();
  } catch (const IoError& e) {
    GTEST_SKIP() << e.what();
  }
  TempDir dir;
  const Mesh m = icosphere(2, 1.0);
  Eigen::VectorXd labels = Eigen::VectorXd::Zero(m.n_edges());
  labels.head(20).setOnes();
  write_edge_values(m, labels, "label", dir / "e.ply");
  write_mesh(m, dir / "a.ply");
  write_mesh(icosphere(3, 1.05), dir / "b.ply");
  const auto r = run_cli("view " + dir / "a.ply" + " " + dir / "b.ply" + " -o " + dir / "p.html --reference " +
                         dir / "b.ply" + " --edges " + dir / "e.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json d = page_data(geotex::test::read_file(dir / "p.html"));
  ASSERT_EQ(d["meshes"].size(), 2u);
  EXPECT_EQ(d["initialField"], "error");
  const auto err_a = decode<float>(d["meshes"][0]["fields"]["error"]);
  ASSERT_EQ(err_a.size(), m.n_vertices());
  for (float e : err_a) EXPECT_NEAR(e, 0.05, 0.01);  // radius 1 against radius 1.05
  EXPECT_EQ(decode<uint32_t>(d["meshes"][0]["edges"]).size(), 40u);
  EXPECT_FALSE(d["meshes"][1].contains("edges"));
}

// The page in Debian's headless Chromium (Playwright from npm drives /usr/bin/chromium).
TEST(ViewerChromium, PageLoadsAndShowsEveryMesh) {
  const fs::path viewer = fs::path(GEOTEX_SOURCE_DIR) / "viewer";
  if (!fs::exists("/usr/bin/chromium")) GTEST_SKIP() << "/usr/bin/chromium not found (scripts/setup_viewer.sh installs it)";
  if (!have_node()) GTEST_SKIP() << "node not found (scripts/setup_viewer.sh installs it)";
  if (!fs::exists(viewer / "node_modules" / "playwright-core"))
    GTEST_SKIP() << "viewer/node_modules/playwright-core missing (run scripts/setup_viewer.sh)";
  try {
    viewer_script();
  } catch (const IoError& e) {
    GTEST_SKIP() << e.what();
  }
  TempDir dir;
  const TexturedShape s = make_shape("spiky-sphere", 1);
  const MatrixX3d V = positions(s.textured);
  PlyExtras x;
  x.vertex_scalars["height"] = std::vector<double>(V.col(2).data(), V.col(2).data() + V.rows());
  write_ply(s.textured, dir / "spiky.ply", x);
  write_mesh(s.base, dir / "base.ply");
  // The base sphere's equator as labelled edges (a red ring).
  const MatrixX3d B = positions(s.base);
  const MatrixX2i E = edges(s.base);
  Eigen::VectorXd ring = Eigen::VectorXd::Zero(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e)
    ring[e] = std::abs(B(E(e, 0), 2)) < 0.08 && std::abs(B(E(e, 1), 2)) < 0.08 ? 1.0 : 0.0;
  ASSERT_GT(ring.sum(), 20);
  write_edge_values(s.base, ring, "label", dir / "ring.ply");
  const auto r = run_cli("view " + dir / "base.ply" + " " + dir / "spiky.ply" + " -o " + dir / "page.html --edges " +
                         dir / "ring.ply");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The screenshot stays in the build folder for people to look at.
  const fs::path shots = fs::current_path() / "viewer-screenshots";
  fs::create_directories(shots);
  const std::string log = dir / "check.log";
  const std::string cmd = "cd " + viewer.string() + " && node test/viewer_check.mjs " + dir / "page.html" + " " +
                          (shots / "two-meshes.png").string() + " 2 >" + log + " 2>&1";
  const int status = std::system(cmd.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  const std::string out = geotex::test::read_file(log);
  if (code == 77) GTEST_SKIP() << out;
  EXPECT_EQ(code, 0) << out;
  EXPECT_TRUE(fs::exists(shots / "two-meshes.png"));
  std::printf("%s", out.c_str());
}
