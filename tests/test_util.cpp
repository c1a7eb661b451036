#include "test_util.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "geotex/core/resources.h"
#include "geotex/core/spatial.h"
#include "geotex/tools/shapes.h"

namespace geotex::test {

Mesh soup(const std::vector<Vec3>& V, const std::vector<Eigen::Vector3i>& F) {
  MatrixX3d X(static_cast<Eigen::Index>(V.size()), 3);
  for (size_t i = 0; i < V.size(); ++i) X.row(static_cast<Eigen::Index>(i)) = V[i];
  MatrixX3i G(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t f = 0; f < F.size(); ++f) G.row(static_cast<Eigen::Index>(f)) = F[f];
  return make_mesh(X, G);
}

Mesh tube_on_a_ball(const Vec3& axis, int segments, int rings) {
  const Mesh ball = icosphere(3);
  const MatrixX3d B = positions(ball);
  const MatrixX3i Fb = faces(ball);
  const TriangleTree tree(B, Fb);
  const Vec3 a = axis.normalized(), u = a.unitOrthogonal(), w = a.cross(u);
  const Eigen::Index nb = B.rows(), nt = static_cast<Eigen::Index>(segments) * (rings + 1);
  MatrixX3d X(nb + nt, 3);
  X.topRows(nb) = B;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double t = 2 * M_PI * (s + 0.5) / segments;
      const Vec3 p = 0.9 * a + 0.25 * (std::cos(t) * u + std::sin(t) * w) + (0.7 * r / rings) * a;
      X.row(nb + r * segments + s) = (r == 0 ? tree.closest(p).point : p).transpose();
    }
  MatrixX3i F(Fb.rows() + 2 * segments * rings, 3);
  F.topRows(Fb.rows()) = Fb;
  for (int r = 0, k = static_cast<int>(Fb.rows()); r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int i = static_cast<int>(nb) + r * segments, j = i + segments, s1 = (s + 1) % segments;
      F.row(k++) = Eigen::RowVector3i(i + s, i + s1, j + s1);
      F.row(k++) = Eigen::RowVector3i(i + s, j + s1, j + s);
    }
  return make_mesh(X, F);
}

// One BLAS thread in every test binary, as the CLI and Python use (resources.h: OpenBLAS's workers spin).
[[maybe_unused]] const int kBlasThreadsBefore = set_blas_threads(1);

extern "C" void __asan_init() __attribute__((weak));
bool address_sanitizer() { return &__asan_init != nullptr; }
const char* cli_path() { return GEOTEX_CLI; }
const char* source_dir() { return GEOTEX_SOURCE_DIR; }


namespace fs = std::filesystem;

TempDir::TempDir() {
  std::random_device rd;
  path = fs::temp_directory_path() / ("geotex-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
  fs::create_directories(path);
}
TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path, ec);
}

fs::path data_dir() {
  if (const char* env = std::getenv("GEOTEX_DATA")) {
    if (fs::is_directory(env)) return env;
  }
  const fs::path p = GEOTEX_DATA_DIR;
  if (fs::is_directory(p) && fs::exists(p / "fandisk.obj")) return p;
  return {};
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CliResult run_cli(const std::string& args) {
  TempDir tmp;
  const std::string out = tmp / "out.txt", err = tmp / "err.txt";
  const std::string cmd = std::string(GEOTEX_CLI) + " " + args + " >" + out + " 2>" + err + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

}  // namespace geotex::test
