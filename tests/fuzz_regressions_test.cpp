// Inputs found by scripts/fuzz.sh (and hand-made neighbours of them): each must read or fail with a
// geotex error, quickly, without a crash. CTest's timeout catches hangs.

#include <filesystem>

#include <gtest/gtest.h>

#include "geotex/error.h"
#include "geotex/io.h"
#include "test_util.h"

TEST(FuzzRegressions, EveryInputReadsOrFailsCleanly) {
  const std::filesystem::path dir = std::filesystem::path(GEOTEX_SOURCE_DIR) / "tests" / "fuzz_regressions";
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    ++n;
    const std::string bytes = geotex::test::read_file(e.path().string());
    SCOPED_TRACE(e.path().filename().string());
    try {
      geotex::read_mesh(e.path());
    } catch (const geotex::Error&) {
    }
    if (e.path().extension() == ".ply") {
      try {
        geotex::parse_ply_bytes(bytes);
      } catch (const geotex::Error&) {
      }
    }
  }
  EXPECT_GT(n, 0u);
}
