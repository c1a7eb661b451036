// Readers of user files besides meshes (user_files.h): deformation handles, feature weights, point clouds.

#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/tools/shapes.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/feature_file.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::TempDir;
using geotex::test::read_file;
using geotex::test::write_file;

namespace {

// Four vertices of a unit square in z = 0, and one above its centre.
MatrixX3d square_points() {
  MatrixX3d X(5, 3);
  X << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1;
  return X;
}

}  // namespace

TEST(Handles, VertexIdsWithTargetsAndWeights) {
  const MatrixX3d X = square_points();
  const HandleSet h = parse_handles(R"({"handles": [{"vertices": [0, 2], "targets": [[1,2,3],[4,5,6]], "weight": 3},
                                                     {"vertices": [4]}]})",
                                    X, 0.5);
  ASSERT_EQ(h.ids, (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(h.weights, (std::vector<double>{3, 3, 0.5}));
  ASSERT_EQ(h.targets.rows(), 3);
  EXPECT_EQ(h.targets.row(0), Eigen::RowVector3d(1, 2, 3));
  EXPECT_EQ(h.targets.row(1), Eigen::RowVector3d(4, 5, 6));
  EXPECT_EQ(h.targets.row(2), X.row(4));  // no transform: stays put
}

TEST(Handles, RegionsAndTransformsMatchTheirFormula) {
  const MatrixX3d X = square_points();
  // Box around the bottom edge (vertices 0, 1), moved by x ↦ R(s (x − c)) + c + t with the default c
  // (their centroid (0.5, 0, 0)), s = 2, a 90° turn about z, and t = (0, 0, 1).
  const HandleSet h = parse_handles(R"({"handles": [{"box": {"min": [-0.1,-0.1,-0.1], "max": [1.1, 0.1, 0.1]},
      "scale": 2, "rotate": {"axis": [0,0,1], "angle_deg": 90}, "translate": [0,0,1]},
      {"sphere": {"center": [0.5,0.5,1], "radius": 0.01}}]})",
                                    X, 1.0);
  ASSERT_EQ(h.ids, (std::vector<int>{0, 1, 4}));
  // Vertex 0: s (x − c) = (−1, 0, 0); turned 90° about z: (0, −1, 0); + c + t = (0.5, −1, 1).
  EXPECT_TRUE(h.targets.row(0).isApprox(Eigen::RowVector3d(0.5, -1, 1), 1e-12)) << h.targets.row(0);
  EXPECT_TRUE(h.targets.row(1).isApprox(Eigen::RowVector3d(0.5, 1, 1), 1e-12)) << h.targets.row(1);
  EXPECT_EQ(h.targets.row(2), X.row(4));
}

TEST(Handles, MalformedDocumentsAreTypedErrors) {
  const MatrixX3d X = square_points();
  auto parse = [&](const std::string& text) { return parse_handles(text, X, 1.0, "h.json"); };
  EXPECT_THROW(parse("{ not json"), IoError);
  EXPECT_THROW(parse(""), IoError);
  const char* unusable[] = {
      R"([])",
      R"({"handles": []})",
      R"({"handles": 3})",
      R"({"handles": [1]})",
      R"({"handles": [{}]})",
      R"({"handles": [{"vertices": [0], "sphere": {"center": [0,0,0], "radius": 1}}]})",
      R"({"handles": [{"vertices": 0}]})",
      R"({"handles": [{"vertices": [5]}]})",
      R"({"handles": [{"vertices": [-1]}]})",
      R"({"handles": [{"vertices": [1.5]}]})",
      R"({"handles": [{"vertices": [1e300]}]})",
      R"({"handles": [{"vertices": [18446744073709551615]}]})",
      R"({"handles": [{"vertices": ["0"]}]})",
      R"({"handles": [{"vertices": [0, 0]}]})",
      R"({"handles": [{"vertices": [0]}, {"box": {"min": [-1,-1,-1], "max": [0.1,0.1,0.1]}}]})",
      R"({"handles": [{"vertices": [0], "targets": [[1,2]]}]})",
      R"({"handles": [{"vertices": [0], "targets": [[1,2,3],[4,5,6]]}]})",
      R"({"handles": [{"vertices": [0], "targets": 7}]})",
      R"({"handles": [{"sphere": {"center": [0,0,0], "radius": 1}, "targets": [[0,0,0]]}]})",
      R"({"handles": [{"sphere": [0,0,0]}]})",
      R"({"handles": [{"sphere": {"center": [0,0,0]}}]})",
      R"({"handles": [{"sphere": {"center": [0,0,0], "radius": "big"}}]})",
      R"({"handles": [{"sphere": {"center": [9,9,9], "radius": 0.1}}]})",
      R"({"handles": [{"box": {"min": [0,0,0]}}]})",
      R"({"handles": [{"vertices": [0], "weight": 0}]})",
      R"({"handles": [{"vertices": [0], "weight": -1}]})",
      R"({"handles": [{"vertices": [0], "weight": "heavy"}]})",
      R"({"handles": [{"vertices": [0], "scale": 0}]})",
      R"({"handles": [{"vertices": [0], "scale": 1e308, "translate": [0,0,0], "center": [-1e308,0,0]}]})",
      R"({"handles": [{"vertices": [0], "rotate": {"axis": [0,0,0], "angle_deg": 10}}]})",
      R"({"handles": [{"vertices": [0], "rotate": {"axis": [0,0,1]}}]})",
      R"({"handles": [{"vertices": [0], "rotate": 5}]})",
      R"({"handles": [{"vertices": [0], "translate": [0,0]}]})",
  };
  for (const char* text : unusable) EXPECT_THROW(parse(text), InvalidInput) << text;
}

TEST(Handles, FileVersionNamesTheFile) {
  TempDir tmp;
  geotex::test::write_file(tmp / "h.json", R"({"handles": [{"vertices": [7]}]})");
  try {
    read_handles(tmp / "h.json", square_points(), 1.0);
    FAIL() << "vertex 7 of 5 was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("h.json: handle 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_handles(tmp / "missing.json", square_points(), 1.0), IoError);
  EXPECT_THROW(read_handles(tmp.path, square_points(), 1.0), IoError);  // a folder
}

TEST(FeatureFiles, TextWeightsAreOnePerLineInZeroOne) {
  const Eigen::VectorXd w = parse_feature_weights("# weights\n0\n  1 \r\n\n0.25\n", 3);
  EXPECT_EQ(w, Eigen::Vector3d(0, 1, 0.25));
  EXPECT_THROW(parse_feature_weights("0\n1\n", 3), InvalidInput);          // too few
  EXPECT_THROW(parse_feature_weights("0\n1\n0\n1\n", 3), InvalidInput);    // too many
  EXPECT_THROW(parse_feature_weights("0\n1\n2\n", 3), InvalidInput);       // outside [0, 1]
  EXPECT_THROW(parse_feature_weights("0\n1\nx\n", 3), IoError);
  EXPECT_THROW(parse_feature_weights("0\n1\nnan\n", 3), IoError);
  EXPECT_THROW(parse_feature_weights("0\n1\n1e999\n", 3), IoError);
  EXPECT_THROW(parse_feature_weights("0\n1\n0 1\n", 3), IoError);          // two numbers on a line
  EXPECT_THROW(parse_feature_weights(std::string("0\n1\n\0\n", 6), 3), IoError);
}

TEST(FeatureFiles, PlyFeatureOrThresholdedHeightIsRead) {
  TempDir tmp;
  const Mesh m = make_shape("cube", 0).textured;
  const size_t n = m.n_vertices();
  PlyExtras x;
  x.vertex_scalars["feature"].assign(n, 0.0);
  x.vertex_scalars["feature"][3] = 1.0;
  write_ply(m, tmp / "f.ply", x);
  const Eigen::VectorXd f = read_feature_file(tmp / "f.ply", m);
  ASSERT_EQ(f.size(), static_cast<Eigen::Index>(n));
  EXPECT_EQ(f.sum(), 1.0);
  EXPECT_EQ(f[3], 1.0);
  // Heights: one vertex far above the threshold; no dilation gives exactly that vertex.
  PlyExtras hx;
  hx.vertex_scalars["height"].assign(n, 0.0);
  hx.vertex_scalars["height"][5] = 10.0;
  write_ply(m, tmp / "h.ply", hx);
  const Eigen::VectorXd g = read_feature_file(tmp / "h.ply", m, {.height_threshold = 0.5, .dilate = 0});
  EXPECT_EQ(g.sum(), 1.0);
  EXPECT_EQ(g[5], 1.0);
  // Errors: another vertex count, no property, out-of-range or non-finite weights.
  EXPECT_THROW(read_feature_file(tmp / "f.ply", make_shape("cube", 1).textured), InvalidInput);
  write_ply(m, tmp / "none.ply", PlyExtras{});
  EXPECT_THROW(read_feature_file(tmp / "none.ply", m), InvalidInput);
  x.vertex_scalars["feature"][0] = 1.5;
  write_ply(m, tmp / "big.ply", x);
  EXPECT_THROW(read_feature_file(tmp / "big.ply", m), InvalidInput);
  // geotex does not write NaN: patch a written marker value into one.
  const double marker = 12345.678, nan = std::nan("");
  hx.vertex_scalars["height"][0] = marker;
  write_ply(m, tmp / "nan.ply", hx);
  std::string bytes = read_file(tmp / "nan.ply");
  const size_t at = bytes.find(std::string(reinterpret_cast<const char*>(&marker), sizeof(double)));
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, sizeof(double), std::string(reinterpret_cast<const char*>(&nan), sizeof(double)));
  write_file(tmp / "nan.ply", bytes);
  EXPECT_THROW(read_feature_file(tmp / "nan.ply", m), InvalidInput);
  // A property declared twice would hold 2 #V values: the PLY parser refuses it.
  const std::string twice =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float feature\nproperty float feature\n"
      "end_header\n0 1 0\n1 0 1\n";
  EXPECT_THROW(parse_ply_bytes(twice), IoError);
}

TEST(PointFiles, PointsAreReadFromTextObjAndPly) {
  const MatrixX3d P = parse_point_text("# cloud\n1 2 3\n\n4 5 6 7 8\r\n", false);
  ASSERT_EQ(P.rows(), 2);
  EXPECT_EQ(P.row(1), Eigen::RowVector3d(4, 5, 6));  // extra columns ignored
  const MatrixX3d Q = parse_point_text("# obj\nv 1 2 3\nvn 0 0 1\nf 1 1 1\nv 4 5 6\n", true);
  ASSERT_EQ(Q.rows(), 2);
  EXPECT_EQ(Q.row(0), Eigen::RowVector3d(1, 2, 3));
  EXPECT_THROW(parse_point_text("1 2\n", false), IoError);
  EXPECT_THROW(parse_point_text("1 2 x\n", false), IoError);
  EXPECT_THROW(parse_point_text("v 1 2\n", true), IoError);
  EXPECT_THROW(parse_point_text("# nothing\n", false), InvalidInput);
  EXPECT_THROW(parse_point_text("f 1 2 3\n", true), InvalidInput);
  EXPECT_THROW(parse_point_text("1 2 inf\n", false), InvalidInput);
  EXPECT_THROW(parse_point_text("1 2 nan\n", false), InvalidInput);

  TempDir tmp;
  const Mesh m = make_shape("sphere", 0).textured;
  write_mesh(m, tmp / "s.ply");
  write_mesh(m, tmp / "s.obj");
  const MatrixX3d X = positions(m);
  EXPECT_TRUE(read_point_file(tmp / "s.ply").isApprox(X));
  EXPECT_TRUE(read_point_file(tmp / "s.obj").isApprox(X, 1e-9));
  EXPECT_FALSE(is_point_file(tmp / "s.off"));
  EXPECT_TRUE(is_point_file("A.XYZ"));
  EXPECT_THROW(read_point_file(tmp / "s.off"), IoError);
  EXPECT_THROW(points_from_ply(parse_ply_bytes("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                               "property float y\nend_header\n0 0\n")),
               IoError);
}

TEST(UserFilesCli, DeformResizeSurfelsReadThroughTheLibrary) {
  TempDir tmp;
  write_mesh(plane(6), tmp / "p.ply");
  // Duplicate handle vertices name both handles.
  geotex::test::write_file(tmp / "dup.json", R"({"handles": [{"vertices": [0, 1]}, {"vertices": [1]}]})");
  auto d = geotex::test::run_cli("deform " + tmp / "p.ply" + " --handles " + tmp / "dup.json" + " -o " + tmp / "d.ply");
  EXPECT_NE(d.exit_code, 0);
  EXPECT_NE(d.err.find("already a handle vertex (handle 0)"), std::string::npos) << d.err;
  EXPECT_EQ(std::count(d.err.begin(), d.err.end(), '\n'), 1) << d.err;
  // A NaN weight in a feature file is refused with the line number.
  std::string text;
  for (size_t i = 0; i < read_mesh(tmp / "p.ply").n_vertices(); ++i) text += i == 2 ? "nan\n" : "0\n";
  geotex::test::write_file(tmp / "f.txt", text);
  auto r = geotex::test::run_cli("resize " + tmp / "p.ply" + " -o " + tmp / "r.ply" + " --scale 2,1,1 --features " +
                                 tmp / "f.txt");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("f.txt:3"), std::string::npos) << r.err;
  // Points: an XYZ file with a short line.
  geotex::test::write_file(tmp / "pts.xyz", "0 0 0\n1 0 0\n0 1\n");
  auto s = geotex::test::run_cli("surfels " + tmp / "pts.xyz" + " -o " + tmp / "s.ply");
  EXPECT_NE(s.exit_code, 0);
  EXPECT_NE(s.err.find("pts.xyz:3"), std::string::npos) << s.err;
}
