// libFuzzer target for geotex's readers. Built once per format by scripts/fuzz.sh with
// -DGEOTEX_FUZZ_FORMAT=<Obj|Ply|Off|Stl|PlyData>. Any input must either read or throw geotex::Error:
// a crash, hang, leak, or sanitizer report is a bug.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "geotex/core/error.h"
#include "geotex/core/io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
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
  return 0;
}
