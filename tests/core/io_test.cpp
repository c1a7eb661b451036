#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::TempDir;
using geotex::test::write_file;

namespace {

// Positions that exercise full double precision (not representable in short decimals).
Mesh awkward_sphere() {
  Mesh m = icosphere(2, 1.0 / 3.0);
  MatrixX3d V = positions(m);
  V.col(0) *= M_PI;
  V.col(1) += Eigen::VectorXd::Constant(V.rows(), 1e-9);
  set_positions(m, V);
  return m;
}

void expect_same(const Mesh& a, const Mesh& b, bool exact) {
  ASSERT_EQ(a.n_vertices(), b.n_vertices());
  ASSERT_EQ(a.n_faces(), b.n_faces());
  const MatrixX3d Va = positions(a), Vb = positions(b);
  if (exact) EXPECT_TRUE(Va == Vb) << "max diff " << (Va - Vb).cwiseAbs().maxCoeff();
  else EXPECT_LT((Va - Vb).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_TRUE(faces(a) == faces(b));
}

}  // namespace

TEST(Io, RoundTripIsExactForEveryTextAndDoubleFormat) {
  TempDir tmp;
  const Mesh m = awkward_sphere();
  for (std::string name : {"a.obj", "a.off", "a.ply"}) {
    for (bool binary : {true, false}) {
      WriteOptions w;
      w.binary = binary;
      write_mesh(m, tmp / name, w);
      expect_same(m, read_mesh(tmp / name), true);
    }
  }
}

TEST(Io, StlRoundTripIsExactForFloatCoordinates) {
  // STL stores float32 and no connectivity: vertices are re-merged by exact coordinate equality,
  // so the order of first appearance defines the vertex order; compare as sets of triangles.
  TempDir tmp;
  Mesh m = icosphere(2);
  MatrixX3d V = positions(m);
  for (Eigen::Index i = 0; i < V.size(); ++i) V.data()[i] = static_cast<float>(V.data()[i]);
  set_positions(m, V);
  for (bool binary : {true, false}) {
    WriteOptions w;
    w.binary = binary;
    write_mesh(m, tmp / "a.stl", w);
    ReadReport rep;
    const Mesh r = read_mesh(tmp / "a.stl", {}, &rep);
    ASSERT_EQ(r.n_vertices(), m.n_vertices());
    ASSERT_EQ(r.n_faces(), m.n_faces());
    EXPECT_EQ(rep.merged_vertices, 3 * m.n_faces() - m.n_vertices());
    const MatrixX3d Vr = positions(r);
    const MatrixX3i Fm = faces(m), Fr = faces(r);
    for (Eigen::Index f = 0; f < Fm.rows(); ++f)
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(Vr.row(Fr(f, k)) == V.row(Fm(f, k)));
  }
}

TEST(Io, PlyExtraPropertiesSurviveAWriteAndRead) {
  TempDir tmp;
  const Mesh m = icosphere(1);
  PlyExtras x;
  std::vector<double> height(m.n_vertices());
  for (size_t i = 0; i < height.size(); ++i) height[i] = 0.1 * i - 1.0 / 3.0;
  x.vertex_scalars["height"] = height;
  PlyExtras::Element e{"edge", {}, {}};
  const MatrixX2i E = edges(m);
  for (Eigen::Index i = 0; i < E.rows(); ++i) {
    e.int_props["vertex1"].push_back(E(i, 0));
    e.int_props["vertex2"].push_back(E(i, 1));
    e.double_props["tilt"].push_back(std::sqrt(double(i)));
  }
  x.elements.push_back(e);
  for (bool binary : {true, false}) {
    write_ply(m, tmp / "t.ply", x, binary);
    const PlyData d = read_ply_data(tmp / "t.ply");
    ASSERT_NE(d.find("edge"), nullptr);
    EXPECT_EQ(d.find("vertex")->scalars.at("height"), height);
    EXPECT_EQ(d.find("edge")->scalars.at("tilt"), e.double_props["tilt"]);
    EXPECT_EQ(d.find("edge")->count, E.rows());
    expect_same(m, read_mesh(tmp / "t.ply"), true);  // the mesh reader ignores the extra element
  }
}

TEST(Io, ObjSlashFormsNegativeIndicesAndQuadsAreRead) {
  TempDir tmp;
  // A quad (triangulated as a fan), slash forms, negative indices, normals and comments.
  write_file(tmp / "q.obj",
             "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n"
             "f 1/1/1 2//1 3 4\nv 2 0 0\nf -4 -1 -3\n");
  ReadReport rep;
  const Mesh m = read_mesh(tmp / "q.obj", {}, &rep);
  EXPECT_EQ(m.n_vertices(), 5u);
  EXPECT_EQ(m.n_faces(), 3u);
  EXPECT_EQ(rep.triangulated_polygons, 1u);
}

TEST(Io, PlyTriangleStripsAreDecoded) {
  TempDir tmp;
  // A strip over a 2x3 grid: 0 1 2 / 3 4 5, strip 0 3 1 4 2 5 gives 4 triangles, consistently oriented.
  write_file(tmp / "s.ply",
             "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
             "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n6 0 3 1 4 2 5\n");
  ReadReport rep;
  const Mesh m = read_mesh(tmp / "s.ply", {}, &rep);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_EQ(rep.strip_triangles, 4u);
  EXPECT_EQ(rep.build.nonmanifold_faces, 0u);
  const MatrixX3d N = face_normals(m);
  for (Eigen::Index f = 0; f < N.rows(); ++f) EXPECT_NEAR(std::abs(N(f, 2)), 1.0, 1e-12);
  for (Eigen::Index f = 1; f < N.rows(); ++f) EXPECT_DOUBLE_EQ(N(f, 2), N(0, 2));  // one orientation
}

// ---- bad input: each case gives its own clear error ----

struct BadCase {
  const char* name;
  const char* file;
  std::string content;
  const char* expect;  // substring of the message
  bool invalid_input;  // InvalidInput (else IoError)
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, IsRefusedWithATypedErrorSayingWhy) {
  const BadCase& c = GetParam();
  TempDir tmp;
  write_file(tmp / c.file, c.content);
  try {
    read_mesh(tmp / c.file);
    FAIL() << "no error for " << c.name;
  } catch (const InvalidInput& e) {
    EXPECT_TRUE(c.invalid_input) << c.name << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
  } catch (const IoError& e) {
    EXPECT_FALSE(c.invalid_input) << c.name << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
  }
}

std::string binary_ply_header(int nv, int nf) {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(nv) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(nf) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadInput,
    ::testing::Values(
        BadCase{"empty", "e.obj", "", "empty", false},
        BadCase{"garbage", "g.ply", std::string("\x7f\x45\x4c\x46\x02\x01garbage", 12), "not a PLY", false},
        BadCase{"bad number", "n.obj", "v 0 0 zero\n", "not a number", false},
        BadCase{"short vertex", "t.obj", "v 0 0 0\nv 1 0 0\nv 1 1", "coordinate", false},
        BadCase{"short face", "f.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2", "at least 3", false},
        BadCase{"nan", "nan.obj", "v 0 0 0\nv nan 0 0\nv 1 1 0\nf 1 2 3\n", "non-finite", true},
        BadCase{"inf", "inf.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n1 1 0\n3 0 1 2\n", "non-finite", true},
        BadCase{"index out of range", "r.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n", "refers to vertex", true},
        BadCase{"no faces", "nf.obj", "v 0 0 0\nv 1 0 0\n", "no faces", true},
        BadCase{"truncated off", "t.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n", "truncated", false},
        BadCase{"truncated ply", "t.ply", binary_ply_header(3, 1) + std::string(20, '\0'), "truncated", false},
        BadCase{"ply without end_header", "h.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "end_header", false},
        BadCase{"truncated stl", "t.stl", std::string(80, ' ') + std::string("\x05\0\0\0", 4) + std::string(60, '\0'), "truncated", false},
        BadCase{"unknown extension", "a.xyz", "1 2 3\n", "unknown mesh format", false},
        BadCase{"all faces degenerate", "d.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 1 2\n", "no usable face", true}),
    [](const ::testing::TestParamInfo<BadCase>& i) {
      std::string s = i.param.name;
      for (auto& ch : s)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return s;
    });

TEST(Io, MissingFileAndDirectory) {
  TempDir tmp;
  EXPECT_THROW(read_mesh(tmp / "nope.obj"), IoError);
  EXPECT_THROW(read_mesh(tmp.path), IoError);
}

TEST(Io, NonManifoldDuplicateAndDegenerateFacesAreCountedNotSilent) {
  TempDir tmp;
  // Three triangles on one edge (0,1): the third is non-manifold. Plus a duplicate and a degenerate.
  write_file(tmp / "nm.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
             "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 2 3\nf 3 3 4\n");
  ReadReport rep;
  const Mesh m = read_mesh(tmp / "nm.obj", {}, &rep);
  EXPECT_EQ(m.n_faces(), 2u);
  EXPECT_EQ(rep.build.nonmanifold_faces, 1u);
  EXPECT_EQ(rep.build.duplicate_faces, 1u);
  EXPECT_EQ(rep.build.degenerate_faces, 1u);
  EXPECT_EQ(rep.build.isolated_vertices, 1u);
  EXPECT_GE(rep.warnings.size(), 3u);
  ReadOptions strict;
  strict.strict = true;
  EXPECT_THROW(read_mesh(tmp / "nm.obj", strict), InvalidInput);
}

TEST(Io, FailedWriteLeavesExistingFileIntact) {
  TempDir tmp;
  const Mesh m = icosphere(1);
  write_mesh(m, tmp / "keep.obj");
  const std::string before = test::read_file(tmp / "keep.obj");
  EXPECT_THROW(write_mesh(m, tmp / "missing-dir/out.obj"), IoError);
  EXPECT_THROW(write_mesh(m, tmp / "out.unknown"), IoError);
  EXPECT_EQ(test::read_file(tmp / "keep.obj"), before);
  // No temporary files are left behind.
  size_t n = 0;
  for (auto& e : std::filesystem::directory_iterator(tmp.path)) n += e.path().filename().string().rfind(".", 0) == 0;
  EXPECT_EQ(n, 0u);
}

TEST(IoData, EverySharedMeshReads) {
  GEOTEX_REQUIRE_DATA();
  const auto dir = test::data_dir();
  for (const char* name : {"fandisk.obj", "stanford-bunny.obj", "igea.ply", "spot.obj", "cow.obj", "woody.obj",
                           "cheburashka.obj", "denoise/Fandisk0.3/Noisy.obj", "denoise/Block0.4/Original.obj"}) {
    ReadReport rep;
    const Mesh m = read_mesh(dir / name, {}, &rep);
    EXPECT_GT(m.n_faces(), 1000u) << name;
    EXPECT_EQ(m.n_vertices(), rep.file_vertices + rep.build.added_vertices) << name;  // cow.obj: 1 vertex split
  }
  // igea.ply is stored as triangle strips: it must come back with its faces.
  ReadReport rep;
  const Mesh igea = read_mesh(dir / "igea.ply", {}, &rep);
  EXPECT_EQ(igea.n_vertices(), 134345u);
  EXPECT_GT(rep.strip_triangles, 200000u);
  EXPECT_GT(igea.n_faces(), 260000u);
}
