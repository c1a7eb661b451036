// Inputs found by scripts/fuzz.sh (and hand-made neighbours of them): each must read or fail with a
// geotex error, quickly, without a crash. Every file goes through every reader the fuzzers cover (the
// mesh readers, the PLY data parser, and the user-file readers of fuzz/fuzz_files.cpp), whatever the
// reader it was found by; its name's prefix says which one that was. CTest's timeout catches hangs;
// the sanitizer build (scripts/sanitize.sh) catches memory errors and undefined behaviour.

#include <filesystem>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/tools/shapes.h"
#include "geotex/texture/texture.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/feature_file.h"
#include "geotex/tools/viewer.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

fs::path regressions_dir() { return fs::path(::geotex::test::source_dir()) / "tests" / "fuzz_regressions"; }

template <class F>
void reads_or_throws_geotex_error(F&& f) {
  try {
    f();
  } catch (const geotex::Error&) {
  }
}

}  // namespace

TEST(FuzzRegressions, EveryInputReadsOrFailsCleanly) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(regressions_dir())) {
    ++n;
    const std::string bytes = geotex::test::read_file(e.path().string());
    SCOPED_TRACE(e.path().filename().string());
    reads_or_throws_geotex_error([&] { geotex::read_mesh(e.path()); });
    for (auto f : {geotex::MeshFormat::Obj, geotex::MeshFormat::Ply, geotex::MeshFormat::Off, geotex::MeshFormat::Stl})
      reads_or_throws_geotex_error([&] { geotex::read_mesh_from_bytes(bytes, f); });
    reads_or_throws_geotex_error([&] { geotex::parse_ply_bytes(bytes); });
  }
  EXPECT_GT(n, 0u);
}

// The readers of fuzz/fuzz_files.cpp, on the mesh its seeds were written for.
TEST(FuzzRegressions, EveryInputThroughTheUserFileReaders) {
  using namespace geotex;
  const Mesh mesh = make_shape("cube", 0).textured;
  const size_t nv = mesh.n_vertices();
  const MatrixX3d X = positions(mesh);
  geotex::test::TempDir tmp;
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(regressions_dir())) {
    ++n;
    const std::string bytes = geotex::test::read_file(e.path().string());
    SCOPED_TRACE(e.path().filename().string());
    reads_or_throws_geotex_error([&] { parse_handles(bytes, X, 1.0); });
    reads_or_throws_geotex_error([&] { parse_feature_weights(bytes, nv); });
    reads_or_throws_geotex_error([&] { parse_point_text(bytes, false); });
    reads_or_throws_geotex_error([&] { parse_point_text(bytes, true); });
    reads_or_throws_geotex_error([&] {
      const PlyData d = parse_ply_bytes(bytes);
      reads_or_throws_geotex_error([&] { features_from_ply(d, mesh); });
      reads_or_throws_geotex_error([&] { points_from_ply(d); });
    });
    // The readers that take a path, through copies with the extension they expect.
    const std::string txt = tmp / "input.txt", ply = tmp / "input.ply";
    geotex::test::write_file(txt, bytes);
    geotex::test::write_file(ply, bytes);
    reads_or_throws_geotex_error([&] { read_field_file(txt, nv); });
    reads_or_throws_geotex_error([&] { read_edge_values(ply, "label"); });
    reads_or_throws_geotex_error([&] { read_mesh_layers(ply, nv); });
    reads_or_throws_geotex_error([&] {
      MeshLayers layers;
      read_edge_labels(ply, nv, layers);
    });
    reads_or_throws_geotex_error([&] { read_texture(ply); });
  }
  EXPECT_GT(n, 0u);
}
