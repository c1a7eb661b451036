#pragma once
// Helpers shared by the tests: temporary folders, the shared data folder, running the CLI.

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "geotex/core/mesh.h"

namespace geotex::test {

// True when the AddressSanitizer runtime is linked in (scripts/sanitize.sh), asked at run time. Its shadow
// memory reserves terabytes of address space, so tests that cap the address space (RLIMIT_AS, ulimit -v)
// drop the cap there, and slow tests shrink.
bool address_sanitizer();
inline const bool kAddressSanitizer = address_sanitizer();

//! The geotex CLI of this build, the source tree (defined in test_util.cpp only, not in every test).
const char* cli_path();
const char* source_dir();

//! A fresh temporary folder, removed at destruction.
struct TempDir {
  std::filesystem::path path;
  TempDir();
  ~TempDir();
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

//! A mesh from a vertex list and a face list (a polygon soup as a test writes it out).
Mesh soup(const std::vector<Vec3>& V, const std::vector<Eigen::Vector3i>& F);

//! An open tube (\p segments around, \p rings along) of radius 0.25 standing on the unit icosphere along \p axis: its
//! lower rim's vertices moved onto their closest points on the ball's faces (none on a ball vertex: a rim resting on
//! another part's faces, as the teapot's handle ends on its body), its upper rim 0.6 out. The ball's vertices first.
Mesh tube_on_a_ball(const Vec3& axis, int segments = 16, int rings = 6);

//! ../shared/data, or empty when absent (tests then skip with a message).
std::filesystem::path data_dir();

#define GEOTEX_REQUIRE_DATA()                                                                  \
  do {                                                                                         \
    if (::geotex::test::data_dir().empty())                                                    \
      GTEST_SKIP() << "shared test data not found (expected ../shared/data beside the repo)"; \
  } while (0)

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};
//! Run the geotex CLI with the given argument string (shell-quoted by the caller).
CliResult run_cli(const std::string& args);

//! Write bytes to a file.
void write_file(const std::string& path, const std::string& bytes);
std::string read_file(const std::string& path);

}  // namespace geotex::test
