// libFuzzer targets for geotex's readers. Built once per target by scripts/fuzz.sh with
// -DGEOTEX_FUZZ_FORMAT=<Obj|Ply|Off|Stl>, -DGEOTEX_FUZZ_PLYDATA or -DGEOTEX_FUZZ_ROUNDTRIP.
// Any input must either read or throw geotex::Error: a crash, hang, leak, or sanitizer report is a bug.
// RoundTrip adds a property: a mesh that reads is written (OBJ, OFF, PLY ascii and binary) and reads
// back with exactly the same positions and faces (abort() otherwise, which libFuzzer reports).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string_view>

#include "geotex/core/error.h"
#include "geotex/core/io.h"

#ifdef GEOTEX_FUZZ_ROUNDTRIP
namespace {

void round_trip(const geotex::Mesh& m) {
  static const std::filesystem::path dir = std::filesystem::exists("/dev/shm") ? "/dev/shm" : "/tmp";
  const geotex::MatrixX3d V = geotex::positions(m);
  const geotex::MatrixX3i F = geotex::faces(m);
  for (const char* ext : {".obj", ".off", ".ply", ".ply-ascii"}) {
    const bool ascii = std::string_view(ext) == ".ply-ascii";
    const auto p = dir / ("geotex-fuzz-rt-" + std::to_string(getpid()) + (ascii ? ".ply" : ext));
    geotex::WriteOptions w;
    w.binary = !ascii;
    geotex::write_mesh(m, p, w);  // a mesh that was read is finite: the writer must take it
    geotex::ReadOptions strict;
    strict.strict = true;  // the written mesh needs no repair
    const geotex::Mesh r = geotex::read_mesh(p, strict);
    std::filesystem::remove(p);
    if (!(geotex::positions(r) == V) || !(geotex::faces(r) == F)) {
      std::fprintf(stderr, "round trip through %s changed the mesh\n", ext);
      std::abort();
    }
  }
}

}  // namespace
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
#if defined(GEOTEX_FUZZ_ROUNDTRIP)
  // The first byte picks the reader, the rest is the file.
  if (size < 1) return 0;
  const auto format = static_cast<geotex::MeshFormat>(data[0] % 4);
  geotex::Mesh m;
  try {
    m = geotex::read_mesh_from_bytes(bytes.substr(1), format);
  } catch (const geotex::Error&) {
    return 0;
  }
  round_trip(m);
#else
  try {
#ifdef GEOTEX_FUZZ_PLYDATA
    const geotex::PlyData d = geotex::parse_ply_bytes(bytes);
    (void)d.find("edge");
#else
    const geotex::Mesh m = geotex::read_mesh_from_bytes(bytes, geotex::MeshFormat::GEOTEX_FUZZ_FORMAT);
    (void)m.n_faces();
#endif
  } catch (const geotex::Error&) {
    // expected for malformed input
  }
#endif
  return 0;
}
