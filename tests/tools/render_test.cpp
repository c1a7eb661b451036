// Software rendering and PNG writing: analytic silhouettes, occlusion, colour maps, PNG structure
// checked byte by byte and decoded by an independent inflater (Python's zlib), CLI end to end.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/tools/render.h"
#include "geotex/tools/shapes.h"
#include "geotex/tools/viewer.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::run_cli;
using geotex::test::TempDir;

namespace {

uint32_t be32(const std::string& s, size_t at) {
  return (uint32_t(uint8_t(s[at])) << 24) | (uint32_t(uint8_t(s[at + 1])) << 16) |
         (uint32_t(uint8_t(s[at + 2])) << 8) | uint32_t(uint8_t(s[at + 3]));
}

// Bitwise CRC-32, written independently of the table-driven one under test.
uint32_t crc_bitwise(const std::string& s) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char ch : s) {
    c ^= ch;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

struct Chunk {
  std::string type, data;
};

// Split a PNG into chunks, checking the signature, each length and each CRC.
std::vector<Chunk> parse_png(const std::string& png) {
  std::vector<Chunk> out;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  size_t at = 8;
  while (at + 12 <= png.size()) {
    const uint32_t len = be32(png, at);
    EXPECT_LE(at + 12 + len, png.size());
    Chunk c{png.substr(at + 4, 4), png.substr(at + 8, len)};
    EXPECT_EQ(be32(png, at + 8 + len), crc_bitwise(png.substr(at + 4, 4 + len))) << "CRC of " << c.type;
    out.push_back(c);
    at += 12 + len;
  }
  EXPECT_EQ(at, png.size()) << "trailing bytes after the last chunk";
  return out;
}

size_t differing_pixels(const Image& a, const Image& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.rgb.size(); i += 3)
    if (a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2]) ++n;
  return n;
}

// The box of the pixels that are not background: [x0, x1) × [y0, y1).
struct PixelBox {
  int x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1;
  double cx() const { return 0.5 * (x0 + x1); }
  double cy() const { return 0.5 * (y0 + y1); }
  int w() const { return x1 - x0; }
  int h() const { return y1 - y0; }
};
PixelBox covered_box(const Image& img, int width) {
  PixelBox b;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < width; ++x)
      if (const uint8_t* p = img.pixel(x, y); p[0] != 255 || p[1] != 255 || p[2] != 255)
        b.x0 = std::min(b.x0, x), b.x1 = std::max(b.x1, x + 1), b.y0 = std::min(b.y0, y), b.y1 = std::max(b.y1, y + 1);
  return b;
}

// A torus far from the origin with a stray vertex beside it (the demo's repaired mesh keeps one).
Mesh off_centre_torus(const Vec3& at) {
  const Mesh t = torus(1.0, 0.35, 32, 12);
  MatrixX3d V(t.n_vertices() + 1, 3);
  V << positions(t).rowwise() + at.transpose(), (at + Vec3(9, 9, 9)).transpose();
  return make_mesh(V, faces(t));
}

size_t non_background(const Image& img) {
  size_t n = 0;
  for (size_t i = 0; i < img.rgb.size(); i += 3)
    if (img.rgb[i] != 255 || img.rgb[i + 1] != 255 || img.rgb[i + 2] != 255) ++n;
  return n;
}

}  // namespace

TEST(Render, SphereSilhouetteCoversPiRSquared) {
  const Mesh sphere = icosphere(5, 1.0);
  for (auto view : {ViewDirection::Iso, ViewDirection::Front, ViewDirection::Top}) {
    RenderOptions o;
    o.width = 480;
    o.height = 360;
    o.view = view;
    o.supersampling = 1;
    const Rendering r = render_mesh(sphere, o);
    // Orthographic: the silhouette is a disk of radius scale · 1 (the inscribed polygon loses < 0.1%).
    const double expected = M_PI * r.camera.scale * r.camera.scale;
    EXPECT_NEAR(r.covered_pixels / expected, 1.0, 0.01);
    EXPECT_NEAR(static_cast<double>(non_background(r.image)) / expected, 1.0, 0.01);
    // The fitted disk fills the height minus the margins.
    EXPECT_NEAR(2.0 * r.camera.scale, o.height * (1 - 2 * o.margin), 0.02 * o.height);
    // and it is centred.
    double sx = 0, sy = 0;
    size_t n = 0;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x)
        if (r.image.pixel(x, y)[0] != 255 || r.image.pixel(x, y)[2] != 255) sx += x + 0.5, sy += y + 0.5, ++n;
    EXPECT_NEAR(sx / n, o.width / 2.0, 1.0);
    EXPECT_NEAR(sy / n, o.height / 2.0, 1.0);
  }
}

TEST(Render, SupersamplingKeepsTheCoverage) {
  const Mesh sphere = icosphere(4, 1.0);
  RenderOptions o;
  o.width = 300;
  o.height = 300;
  o.supersampling = 3;
  const Rendering r = render_mesh(sphere, o);
  EXPECT_NEAR(r.covered_pixels / (M_PI * r.camera.scale * r.camera.scale), 1.0, 0.01);
}

TEST(Render, FlatAndSmoothShadeTheSameSilhouetteDifferently) {
  const Mesh sphere = icosphere(2, 1.0);
  RenderOptions o;
  o.width = 200;
  o.height = 200;
  o.supersampling = 1;
  const Rendering smooth = render_mesh(sphere, o);
  o.smooth = false;
  const Rendering flat = render_mesh(sphere, o);
  EXPECT_EQ(smooth.covered_pixels, flat.covered_pixels);
  EXPECT_EQ(non_background(smooth.image), non_background(flat.image));
  EXPECT_GT(differing_pixels(smooth.image, flat.image), smooth.covered_pixels / 2);
}

TEST(Render, FieldColoursFollowTheColourMap) {
  const Mesh sphere = icosphere(4, 1.0);
  const MatrixX3d V = positions(sphere);
  RenderLayers layers;
  layers.field = V.col(2);  // height
  RenderOptions o;
  o.width = 300;
  o.height = 300;
  o.view = ViewDirection::Front;
  o.up = UpAxis::Z;  // screen up is z
  o.supersampling = 1;
  o.legend = false;
  o.specular = 0;
  o.ambient = 1.0;  // unlit: the pixel is exactly the mapped colour
  const Rendering r = render_mesh(sphere, o, layers);
  EXPECT_NEAR(r.field_lo, -1.0, 1e-9);
  EXPECT_NEAR(r.field_hi, 1.0, 1e-9);
  // Screen y = cy − scale·z: sample at z = ±0.7 and 0 on the vertical centre line.
  for (double z : {-0.7, 0.0, 0.7}) {
    const int y = static_cast<int>(std::floor(150 - r.camera.scale * z));
    const Vec3 want = colour_map((z + 1) / 2);
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(r.image.pixel(150, y)[j], 255 * want[j], 6) << "z " << z << " channel " << j;
  }
  // A fixed range maps everything above it to the top colour.
  layers.field_lo = -2;
  layers.field_hi = -1;
  const Rendering top = render_mesh(sphere, o, layers);
  const Vec3 yellow = colour_map(1.0);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(top.image.pixel(150, 150)[j], 255 * yellow[j], 1);
}

// A plate seen from the top with uv = (x, y): the picture is a checkerboard whose squares have the side
// the camera's scale gives checker_size, and the colour flips between neighbouring squares.
TEST(Render, UvCheckerboardFollowsTheCoordinates) {
  const Mesh plate = plane(8, 1.0);  // [-0.5, 0.5]²
  RenderOptions o;
  o.width = o.height = 200;
  o.view = ViewDirection::Top;
  o.up = UpAxis::Z;
  o.supersampling = 1;
  o.specular = 0;
  RenderLayers l;
  const MatrixX3d V = positions(plate);
  l.uv = V.leftCols<2>();
  l.checker_size = 0.25;
  const Rendering r = render_mesh(plate, o, l);
  auto at = [&](double x, double y) {  // the pixel of plate point (x, y)
    const Vec3 d = Vec3(x, y, 0) - r.camera.centre;
    const int px = static_cast<int>(r.camera.scale * d.dot(r.camera.right) + o.width / 2.0);
    const int py = static_cast<int>(-r.camera.scale * d.dot(r.camera.up) + o.height / 2.0);
    return r.image.pixel(px, py)[2];  // the blue channel tells the two colours apart
  };
  // Centres of the 4 × 4 squares: the colour depends only on the parity of the square.
  std::set<int> even, odd;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) ((i + j) % 2 ? odd : even).insert(at(-0.375 + 0.25 * i, -0.375 + 0.25 * j));
  ASSERT_EQ(even.size(), 1u);
  ASSERT_EQ(odd.size(), 1u);
  EXPECT_GT(std::abs(*even.begin() - *odd.begin()), 10);
  // Inside one face the colour changes where uv crosses a square's side (per pixel, not per vertex).
  l.checker_size = 0.0625;  // half of an edge of the 8 × 8 grid
  const Rendering fine = render_mesh(plate, o, l);
  auto fine_at = [&](double x, double y) {
    const Vec3 d = Vec3(x, y, 0) - fine.camera.centre;
    return fine.image.pixel(static_cast<int>(fine.camera.scale * d.dot(fine.camera.right) + o.width / 2.0),
                            static_cast<int>(-fine.camera.scale * d.dot(fine.camera.up) + o.height / 2.0))[2];
  };
  EXPECT_NE(fine_at(0.03, 0.01), fine_at(0.09, 0.01));
  EXPECT_THROW(render_mesh(plate, o, [&] { RenderLayers b = l; b.uv.conservativeResize(3, 2); return b; }()), InvalidInput);
}

TEST(Render, LegendAddsABarBesideTheMesh) {
  const Mesh sphere = icosphere(3, 1.0);
  RenderLayers layers;
  layers.field = positions(sphere).col(0);
  RenderOptions o;
  o.width = 400;
  o.height = 300;
  o.supersampling = 1;
  const Rendering r = render_mesh(sphere, o, layers);
  // The bar's top pixel is the top colour of the map.
  const int bx = o.width - std::min(110, o.width / 4) + 8 + 2, by = o.height / 8;
  const Vec3 yellow = colour_map(1.0);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(r.image.pixel(bx, by)[j], 255 * yellow[j], 1);
  // The mesh is fitted left of the legend.
  EXPECT_LT(r.camera.scale * 2, o.width - std::min(110, o.width / 4) + 1);
}

TEST(Render, EdgeLinesAreDrawnAndHiddenBehindTheSurface) {
  const Mesh sphere = icosphere(3, 1.0);
  const MatrixX3d V = positions(sphere);
  const MatrixX2i E = edges(sphere);
  RenderOptions o;
  o.width = 240;
  o.height = 240;
  o.view = ViewDirection::Front;  // camera on −y
  o.up = UpAxis::Z;
  o.supersampling = 1;
  const Rendering plain = render_mesh(sphere, o);
  auto select = [&](auto keep) {
    std::vector<int> rows;
    for (Eigen::Index e = 0; e < E.rows(); ++e)
      if (keep(V.row(E(e, 0)), V.row(E(e, 1)))) rows.push_back(static_cast<int>(e));
    RenderLayers l;
    l.segments.resize(rows.size(), 2);
    for (size_t i = 0; i < rows.size(); ++i) l.segments.row(i) = E.row(rows[i]);
    return l;
  };
  // Edges on the far side (y > 0.3) are hidden: the picture does not change.
  const RenderLayers back = select([](const auto& a, const auto& b) { return a[1] > 0.3 && b[1] > 0.3; });
  ASSERT_GT(back.segments.rows(), 10);
  EXPECT_EQ(differing_pixels(render_mesh(sphere, o, back).image, plain.image), 0u);
  // Edges on the near side (y < −0.3) show, in the label colour.
  RenderLayers front = select([](const auto& a, const auto& b) { return a[1] < -0.3 && b[1] < -0.3; });
  front.segment_labels = Eigen::VectorXi::Constant(front.segments.rows(), 2);
  const Rendering lined = render_mesh(sphere, o, front);
  EXPECT_GT(differing_pixels(lined.image, plain.image), 500u);
  const Vec3 blue = label_colour(2);
  size_t blue_pixels = 0;
  for (size_t i = 0; i < lined.image.rgb.size(); i += 3)
    if (std::abs(lined.image.rgb[i] - 255 * blue[0]) < 2 && std::abs(lined.image.rgb[i + 2] - 255 * blue[2]) < 2) ++blue_pixels;
  EXPECT_GT(blue_pixels, 300u);
}

TEST(Render, EmptyMeshAndWrongSizedLayersThrow) {
  const Mesh sphere = icosphere(1, 1.0);
  RenderOptions o;
  o.width = 0;
  EXPECT_THROW(render_mesh(sphere, o), InvalidInput);
  RenderLayers l;
  l.field = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(render_mesh(sphere, {}, l), InvalidInput);
  RenderLayers s;
  s.segments.resize(1, 2);
  s.segments << 0, 100000;
  EXPECT_THROW(render_mesh(sphere, {}, s), InvalidInput);
  EXPECT_THROW(view_direction_from_name("side"), InvalidInput);
  EXPECT_THROW(render_mesh(Mesh{}), InvalidInput);
}

TEST(Png, ChunksAndChecksumsAreValid) {
  const Rendering r = render_mesh(icosphere(3, 1.0), RenderOptions{.width = 123, .height = 77});
  const std::string png = encode_png(r.image);
  const auto chunks = parse_png(png);
  ASSERT_GE(chunks.size(), 3u);
  EXPECT_EQ(chunks[0].type, "IHDR");
  EXPECT_EQ(be32(chunks[0].data, 0), 123u);
  EXPECT_EQ(be32(chunks[0].data, 4), 77u);
  EXPECT_EQ(chunks[0].data.substr(8), std::string("\x08\x02\x00\x00\x00", 5));  // 8-bit RGB, not interlaced
  EXPECT_EQ(chunks.back().type, "IEND");
  size_t idat = 0;
  for (const Chunk& c : chunks) {
    idat += c.type == "IDAT";
    EXPECT_TRUE(c.type == "IHDR" || c.type == "IDAT" || c.type == "IEND" || c.type == "sRGB") << c.type;
  }
  EXPECT_GE(idat, 1u);
}

TEST(Png, CompressesUniformAreas) {
  Image img;
  img.width = 800;
  img.height = 600;
  img.rgb.assign(800 * 600 * 3, 200);
  const std::string png = encode_png(img);
  EXPECT_LT(png.size(), img.rgb.size() / 100);
}

TEST(Png, DecodesToTheSamePixelsWithAnIndependentInflater) {
  if (!std::filesystem::exists("/usr/bin/python3")) GTEST_SKIP() << "/usr/bin/python3 not found";
  TempDir dir;
  RenderLayers layers;
  const Mesh sphere = icosphere(3, 1.0);
  layers.field = positions(sphere).col(2);
  const Rendering r = render_mesh(sphere, RenderOptions{.width = 211, .height = 150}, layers);
  write_png(r.image, dir / "a.png");
  // Python's zlib inflates; the script undoes all five PNG filters and writes raw RGB.
  const std::string script = R"(
import sys, zlib, struct
d = open(sys.argv[1], 'rb').read()
at, idat = 8, b''
while at < len(d):
    n, t = struct.unpack('>I4s', d[at:at+8]); body = d[at+8:at+8+n]; at += 12 + n
    if t == b'IHDR': w, h = struct.unpack('>II', body[:8])
    if t == b'IDAT': idat += body
raw = zlib.decompress(idat); s = 3 * w; out = bytearray(); prev = bytearray(s)
for y in range(h):
    f = raw[y*(s+1)]; row = bytearray(raw[y*(s+1)+1:(y+1)*(s+1)])
    for i in range(s):
        a = row[i-3] if i >= 3 else 0; b = prev[i]; c = prev[i-3] if i >= 3 else 0
        if f == 1: row[i] = (row[i] + a) & 255
        elif f == 2: row[i] = (row[i] + b) & 255
        elif f == 3: row[i] = (row[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c; pa, pb, pc = abs(p-a), abs(p-b), abs(p-c)
            row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    out += row; prev = row
open(sys.argv[2], 'wb').write(out)
)";
  geotex::test::write_file(dir / "decode.py", script);
  const std::string cmd = "/usr/bin/python3 " + (dir / "decode.py") + " " + (dir / "a.png") + " " + (dir / "a.rgb");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string rgb = geotex::test::read_file(dir / "a.rgb");
  ASSERT_EQ(rgb.size(), r.image.rgb.size());
  EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), reinterpret_cast<const char*>(r.image.rgb.data())));
}

TEST(Render, DistanceBetweenConcentricSpheresIsTheirGap) {
  const Mesh inner = icosphere(3, 1.0), outer = icosphere(5, 2.0);
  const Eigen::VectorXd d = distance_to_surface(inner, outer);
  ASSERT_EQ(d.size(), static_cast<Eigen::Index>(inner.n_vertices()));
  EXPECT_NEAR(d.minCoeff(), 1.0, 0.01);
  EXPECT_NEAR(d.maxCoeff(), 1.0, 0.01);
  EXPECT_NEAR(distance_to_surface(inner, inner).maxCoeff(), 0.0, 1e-12);
}

TEST(RenderCli, WritesAPngOfTheRequestedSize) {
  TempDir dir;
  Mesh sphere = icosphere(3, 1.0);
  PlyExtras x;
  const MatrixX3d V = positions(sphere);
  x.vertex_scalars["height"] = std::vector<double>(V.col(2).data(), V.col(2).data() + V.rows());
  write_ply(sphere, dir / "s.ply", x);
  write_edge_values(sphere, Eigen::VectorXd::Ones(sphere.n_edges()), "label", dir / "e.ply");
  const auto r = run_cli("render " + (dir / "s.ply") + " -o " + (dir / "s.png") +
                         " --size 320x240 --view top --field height --edges " + (dir / "e.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto chunks = parse_png(geotex::test::read_file(dir / "s.png"));
  ASSERT_FALSE(chunks.empty());
  EXPECT_EQ(be32(chunks[0].data, 0), 320u);
  EXPECT_EQ(be32(chunks[0].data, 4), 240u);
  // Error against a reference as the field, flat shading.
  write_mesh(icosphere(4, 1.1), dir / "ref.ply");
  const auto e = run_cli("render " + (dir / "s.ply") + " -o " + (dir / "e.png") + " --reference " + (dir / "ref.ply") + " --flat");
  EXPECT_EQ(e.exit_code, 0) << e.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "e.png"));
}

TEST(RenderCli, BadArgumentsFailWithOneLine) {
  TempDir dir;
  write_mesh(icosphere(1, 1.0), dir / "s.ply");
  for (const std::string& args : std::vector<std::string>{"--size 0x10", "--size big", "--view side", "--field nosuch",
                                                          "--edges " + (dir / "none.ply")}) {
    const auto r = run_cli("render " + (dir / "s.ply") + " -o " + (dir / "o.png") + " " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_FALSE(r.err.empty()) << args;
    EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << args << ": " << r.err;
  }
  EXPECT_NE(run_cli("render " + (dir / "missing.ply") + " -o " + (dir / "o.png")).exit_code, 0);
  EXPECT_NE(run_cli("render " + (dir / "s.ply") + " -o " + (dir / "o.jpg")).exit_code, 0);
  const auto h = run_cli("render --help");
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("--size"), std::string::npos);
}

TEST(RenderCli, FramingFlagsAcceptValidAndRefuseInvalidValues) {
  TempDir dir;
  write_mesh(off_centre_torus(Vec3(10, 20, 30)), dir / "t.ply");
  for (const std::string& args : std::vector<std::string>{
           "--zoom 0.5 --frame sphere --up y --margin 0.1", "--centre 10,20,30 --zoom 3", "--center 10,20,30",
           "--up auto --view top", "--up -z"}) {
    const auto r = run_cli("render " + (dir / "t.ply") + " -o " + (dir / "t.png") + " --size 64x48 " + args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
  }
  for (const std::string& args : std::vector<std::string>{"--zoom 0", "--zoom -1", "--zoom x", "--frame wide", "--up w",
                                                          "--centre 1,2", "--margin 0.9", "--view side"}) {
    const auto r = run_cli("render " + (dir / "t.ply") + " -o " + (dir / "t.png") + " --size 64x48 " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << args << ": " << r.err;
  }
}

TEST(Render, UpAxisRotatesTheCamera) {
  // A y-up copy of a z-up shape, rendered with up = y, gives the z-up picture.
  const Mesh m = make_shape("spiky-sphere", 0).textured;
  Mesh rotated = m;
  const MatrixX3d V = positions(m);
  MatrixX3d W(V.rows(), 3);
  W << V.col(0), V.col(2), -V.col(1);  // rotation about x taking z to y
  set_positions(rotated, W);
  for (auto view : {ViewDirection::Iso, ViewDirection::Front, ViewDirection::Top}) {
    RenderOptions o;
    o.width = 200;
    o.height = 160;
    o.view = view;
    o.up = UpAxis::Z;
    const Rendering a = render_mesh(m, o);
    o.up = UpAxis::Y;
    const Rendering b = render_mesh(rotated, o);
    EXPECT_LT(differing_pixels(a.image, b.image), 200u * 160u / 200u);  // float rounding at a few edge pixels
    EXPECT_NEAR(a.camera.scale, b.camera.scale, 1e-9 * a.camera.scale);
  }
}

TEST(RenderFraming, AnOffCentreMeshIsCentredInItsPicture) {
  // The projected box of the mesh is centred (to a pixel) whatever the view, up axis, framing and
  // zoom; the stray vertex does not count. Tight framing fills the picture less the margin.
  const Vec3 at(1000, -500, 250);
  const Mesh m = off_centre_torus(at);
  ASSERT_EQ(m.n_vertices(), 32u * 12u + 1u);
  for (auto view : {ViewDirection::Iso, ViewDirection::Front, ViewDirection::Top})
    for (auto up : {UpAxis::Z, UpAxis::Y, UpAxis::Auto})
      for (auto frame : {Framing::Tight, Framing::Sphere}) {
        RenderOptions o{.width = 240, .height = 180, .view = view, .up = up, .frame = frame};
        o.supersampling = 1;
        const Rendering one = render_mesh(m, o);
        const PixelBox b = covered_box(one.image, o.width);
        const std::string what = fmt::format("view {} up {} frame {}", enum_name(view_direction_names(), view),
                                             enum_name(up_axis_names(), up), enum_name(framing_names(), frame));
        EXPECT_NEAR(b.cx(), 120, 1.0) << what;
        EXPECT_NEAR(b.cy(), 90, 1.0) << what;
        const double free = 2 * o.margin * 180;
        if (frame == Framing::Tight)  // one side touches the margin
          EXPECT_NEAR(std::max(b.w() / (240 - free), b.h() / (180 - free)), 1.0, 2.0 / 180) << what;
        else  // the bounding sphere (radius 1.35) fits the height
          EXPECT_NEAR(one.camera.scale, (180 - free) / 2.7, 1e-9) << what;
        o.zoom = 0.5;
        const Rendering half = render_mesh(m, o);
        const PixelBox h = covered_box(half.image, o.width);
        EXPECT_NEAR(half.camera.scale, 0.5 * one.camera.scale, 1e-12 * one.camera.scale) << what;
        EXPECT_NEAR(h.cx(), 120, 1.0) << what;
        EXPECT_NEAR(h.cy(), 90, 1.0) << what;
        EXPECT_NEAR(h.w(), 0.5 * b.w(), 1.5) << what;
      }
}

TEST(RenderFraming, TheMeshIsCentredBesideTheLegend) {
  const Mesh m = off_centre_torus(Vec3(-40, 7, 3));
  RenderLayers l;
  l.field = positions(m).col(0);
  RenderOptions o{.width = 400, .height = 200, .up = UpAxis::Z};
  o.supersampling = 1;
  const Rendering r = render_mesh(m, o, l);
  const int room = 400 - legend_width(400, 200);
  const PixelBox b = covered_box(r.image, room - 4);  // the legend's bar starts 8 pixels into its column
  EXPECT_NEAR(b.cx(), room / 2.0, 1.0);
  EXPECT_NEAR(b.cy(), 100, 1.0);
}

TEST(RenderFraming, CentreAndSphereFraming) {
  const Vec3 at(1000, -500, 250);
  const Mesh m = off_centre_torus(at);
  // Front view with up z: screen right is +x. Centring on a point 0.5 to the right of the torus's
  // centre moves the torus 0.5 · scale pixels left (zoomed out, so that it stays in the picture).
  RenderOptions o{.width = 240, .height = 180, .view = ViewDirection::Front, .up = UpAxis::Z, .zoom = 0.6};
  o.supersampling = 1;
  o.centre = at + Vec3(0.5, 0, 0);
  const Rendering r = render_mesh(m, o);
  const PixelBox b = covered_box(r.image, o.width);
  EXPECT_NEAR(b.cx(), 120 - 0.5 * r.camera.scale, 1.0);
  EXPECT_NEAR(b.cy(), 90, 1.0);
  // Sphere framing: one scale from every direction (tight framing: a torus seen edge-on is larger).
  o.centre.reset();
  o.zoom = 1;
  std::vector<double> tight, sphere;
  for (auto view : {ViewDirection::Iso, ViewDirection::Front, ViewDirection::Top}) {
    o.view = view;
    o.frame = Framing::Tight;
    tight.push_back(fit_camera(m, o).scale);
    o.frame = Framing::Sphere;
    sphere.push_back(fit_camera(m, o).scale);
  }
  EXPECT_GT(std::abs(tight[1] - tight[2]), 0.1 * tight[2]);
  EXPECT_EQ(sphere[0], sphere[1]);
  EXPECT_EQ(sphere[1], sphere[2]);
  // Bad values are refused.
  o.zoom = 0;
  EXPECT_THROW(fit_camera(m, o), InvalidInput);
}

// Every option of the render and viewer tables: its default is valid and survives text and back.
template <class O>
void expect_defaults_round_trip() {
  const O defaults{};
  for (const auto& f : O::table().fields()) {
    const OptionValue v = f.get(defaults);
    O o;
    f.set(o, parse_option_value(f.info, format_option_value(v)));
    EXPECT_EQ(format_option_value(f.get(o)), format_option_value(v)) << f.info.name;
  }
  EXPECT_NO_THROW(O::table().check(defaults));
}

TEST(RenderOptionsTable, DefaultsRoundTripAndBadValuesAreRefused) {
  expect_defaults_round_trip<RenderOptions>();
  expect_defaults_round_trip<ViewerOptions>();
  RenderOptions o;
  const auto& t = RenderOptions::table();
  t.set(o, "centre", parse_option_value(t.find("centre")->info, "1,2,3"));
  EXPECT_EQ(*o.centre, Vec3(1, 2, 3));
  t.set(o, "up", std::string("-y"));
  EXPECT_EQ(o.up, UpAxis::NegY);
  EXPECT_THROW(t.set(o, "zoom", 0.0), InvalidOption);
  EXPECT_THROW(t.set(o, "frame", std::string("wide")), InvalidOption);
  ViewerOptions v;
  EXPECT_THROW(ViewerOptions::table().set(v, "position_bits", int64_t{30}), InvalidOption);
}

// The quick demo (coarse shapes, no real model): the page follows the pipeline, and every figure a step
// asked for has a caption and a picture that exists.
TEST(DemoReport, QuickDemoFollowsThePipelineWithCaptionedPictures) {
  TempDir dir;
  const auto r = run_cli("-q demo --quick -o " + (dir / "demo"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string index = geotex::test::read_file(dir / "demo/index.html");
  size_t last = 0;
  for (const char* section : {"Input", "Toolkit", "Denoising", "Texture", "Resizing"}) {
    const size_t at = index.find(fmt::format("data-section=\"{}\"", section));
    ASSERT_NE(at, std::string::npos) << section;
    EXPECT_GT(at, last) << section << " out of the pipeline's order";
    last = at;
  }
  const auto report = nlohmann::json::parse(geotex::test::read_file(dir / "demo/report.json"));
  size_t figures = 0;
  for (const auto& step : report["steps"]) {
    if (!step.contains("figures")) continue;
    for (const auto& f : step["figures"]) {
      ++figures;
      EXPECT_GT(f["caption"].get<std::string>().size(), 20u) << f["mesh"];
      const std::string png = "pictures/" + std::filesystem::path(f["mesh"].get<std::string>()).stem().string() + ".png";
      EXPECT_TRUE(std::filesystem::exists(dir / ("demo/" + png))) << png;
      EXPECT_NE(index.find(png), std::string::npos) << png;
    }
  }
  EXPECT_GE(figures, 40u);
  // One caption per picture.
  size_t imgs = 0, captions = 0;
  for (size_t p = index.find("<img "); p != std::string::npos; p = index.find("<img ", p + 1)) ++imgs;
  for (size_t p = index.find("<figcaption>"); p != std::string::npos; p = index.find("<figcaption>", p + 1)) ++captions;
  EXPECT_EQ(imgs, figures);
  EXPECT_EQ(captions, figures);
  // Denoising: the default beside the thesis presets, the real model skipped with a note in --quick.
  for (const char* m : {"denoise-cube-default", "denoise-cube-mrf-thesis", "denoise-cube-surfel-thesis"})
    EXPECT_NE(index.find(std::string("pictures/") + m + ".png"), std::string::npos) << m;
  EXPECT_NE(index.find("real model skipped"), std::string::npos);
}

// Without the shared data (a fresh clone), the real-model rows show the shipped spot (CC0), upright,
// full-size pictures behind half-size thumbnails.
TEST(DemoReport, AFreshCloneShowsTheShippedRealModel) {
  TempDir dir;
  std::filesystem::create_directories(dir / "no-shared-data");
  const auto r = run_cli("-q demo --only denoising --only report --data " + (dir / "no-shared-data") + " -o " +
                         (dir / "demo"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string index = geotex::test::read_file(dir / "demo/index.html");
  EXPECT_NE(index.find("pictures/denoise-spot-default.png"), std::string::npos);
  EXPECT_EQ(index.find("skipped"), std::string::npos);
  const std::string png = geotex::test::read_file(dir / "demo/pictures/denoise-spot-default.png");
  ASSERT_GT(png.size(), 24u);
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
           (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
  };
  const uint32_t width = be32(16), height = be32(20);  // the IHDR chunk
  EXPECT_GE(width, 800u);
  EXPECT_NE(index.find(fmt::format("width=\"{}\" height=\"{}\"", width / 2, height / 2)), std::string::npos);
  const auto report = nlohmann::json::parse(geotex::test::read_file(dir / "demo/report.json"));
  bool upright = false;
  for (const auto& step : report["steps"])
    for (const auto& f : step.value("figures", nlohmann::json::array()))
      if (f["mesh"] == "denoise-spot-default.ply") upright = f["up"] == "auto";
  EXPECT_TRUE(upright) << "the real model's up axis is read from it, not the generated shapes' z";
}

TEST(DemoReport, IndexShowsEveryMeshWithItsPicture) {
  TempDir dir;
  const auto r = run_cli("-q demo --only shapes --only report -o " + (dir / "demo"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string index = geotex::test::read_file(dir / "demo/index.html");
  for (const auto& name : shape_names()) {
    EXPECT_NE(index.find("pictures/" + name + ".png"), std::string::npos) << name;
    const std::string png = geotex::test::read_file(dir / ("demo/pictures/" + name + ".png"));
    ASSERT_GT(png.size(), 8u) << name;
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
  }
  // 3D pages when the viewer bundle is available, sharing one copy of the script.
  if (std::filesystem::exists(dir / "demo/views/geotex-viewer.js")) {
    EXPECT_TRUE(std::filesystem::exists(dir / "demo/views/sphere.html"));
    EXPECT_NE(index.find("views/sphere.html"), std::string::npos);
  }
}

// A flat fan of slivers around one vertex (issue 30): each sliver spans half the picture's bounding box
// but few pixels; the rows are scanned over their spans only. The fan is a 2000-gon: its pixels are
// those of the disk, and a coarse fan (its triangles wide) covers the same disk.
TEST(Render, FanOfSliversCoversItsDisk) {
  auto fan = [](int k) {
    MatrixX3d V(k + 1, 3);
    MatrixX3i F(k, 3);
    V.row(0) << 0, 0, 0;
    for (int i = 0; i < k; ++i) {
      V.row(1 + i) << std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0;
      F.row(i) << 0, 1 + i, 1 + (i + 1) % k;
    }
    return make_mesh(V, F);
  };
  RenderOptions o;
  o.width = 400;
  o.height = 400;
  o.view = ViewDirection::Top;
  o.supersampling = 1;
  const Rendering fine = render_mesh(fan(2000), o);
  const double disk = M_PI * fine.camera.scale * fine.camera.scale;
  EXPECT_NEAR(fine.covered_pixels / disk, 1.0, 0.01);
  o.camera = fine.camera;
  const Rendering coarse = render_mesh(fan(400), o);
  EXPECT_NEAR(double(coarse.covered_pixels) / fine.covered_pixels, 1.0, 0.002);
}
