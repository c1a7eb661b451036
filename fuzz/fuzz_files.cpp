// libFuzzer targets for geotex's readers of user files other than meshes. Built once per target by
// scripts/fuzz.sh with -DGEOTEX_FUZZ_FILE_<target>=1:
//   Handles    deformation handles JSON (geotex deform --handles): parse_handles()
//   Numbers    text files of numbers: feature weights (resize --features F.txt), field files
//              (view/render --field-file), point lists (surfels IN.xyz / IN.obj)
//   PlyExtras  PLYs read for their extra properties: resize --features F.ply, surfels IN.ply,
//              compare --labels / texture (read_edge_values), view/render layers and --edges
//   Texture    texture files (texture apply/edit/transfer/animate): read_texture()
// Any input must either read or throw geotex::Error: a crash, hang, leak or sanitizer report is a bug.
// The readers that only take a path get the bytes through a scratch file.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/core/mesh.h"
#include "geotex/tools/shapes.h"
#include "geotex/texture/texture.h"
#include "geotex/core/user_files.h"
#include "geotex/tools/viewer.h"

namespace {

// The mesh of `geotex generate cube --level 0` (152 vertices): the seeds were written for it.
const geotex::Mesh& cube() {
  static const geotex::Mesh m = geotex::make_shape("cube", 0).textured;
  return m;
}

// A scratch file holding the input, for the readers that take a path.
std::filesystem::path scratch(std::string_view bytes, const char* ext) {
  static const std::filesystem::path dir = std::filesystem::exists("/dev/shm") ? "/dev/shm" : "/tmp";
  const auto p = dir / ("geotex-fuzz-" + std::to_string(getpid()) + ext);
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

template <class F>
void expect_geotex_error(F&& f) {
  try {
    f();
  } catch (const geotex::Error&) {
    // expected for malformed input
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const geotex::Mesh& mesh = cube();
  const size_t n = mesh.n_vertices();
  using namespace geotex;
#if GEOTEX_FUZZ_FILE_Handles
  expect_geotex_error([&] { (void)parse_handles(bytes, positions(mesh), 1.0); });
#elif GEOTEX_FUZZ_FILE_Numbers
  expect_geotex_error([&] { (void)parse_feature_weights(bytes, n); });
  expect_geotex_error([&] { (void)parse_point_text(bytes, false); });
  expect_geotex_error([&] { (void)parse_point_text(bytes, true); });
  const auto p = scratch(bytes, ".txt");
  expect_geotex_error([&] { (void)read_field_file(p, n); });
  std::filesystem::remove(p);
#elif GEOTEX_FUZZ_FILE_PlyExtras
  expect_geotex_error([&] {
    const PlyData d = parse_ply_bytes(bytes);
    expect_geotex_error([&] { (void)features_from_ply(d, mesh); });
    expect_geotex_error([&] { (void)points_from_ply(d); });
  });
  const auto p = scratch(bytes, ".ply");
  expect_geotex_error([&] { (void)read_edge_values(p, "label"); });
  expect_geotex_error([&] { (void)read_mesh_layers(p, n); });
  expect_geotex_error([&] {
    MeshLayers layers;
    read_edge_labels(p, n, layers);
  });
  std::filesystem::remove(p);
#elif GEOTEX_FUZZ_FILE_Texture
  const auto p = scratch(bytes, ".ply");
  expect_geotex_error([&] { (void)read_texture(p); });
  std::filesystem::remove(p);
#else
#error "define GEOTEX_FUZZ_FILE_<Handles|Numbers|PlyExtras|Texture>=1"
#endif
  return 0;
}
