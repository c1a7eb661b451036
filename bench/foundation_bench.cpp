// Foundation benchmarks: binary PLY read/write at 10^6 faces; cotangent Laplacian assembly and one
// implicit cotangent smoothing step (assembly + factorization + solve) at 10^4, 10^5, 10^6 faces.
// Run: build/bench/foundation_bench [--benchmark_filter=…]

#include <filesystem>
#include <map>

#include <benchmark/benchmark.h>
#include <unistd.h>

#include "geotex/core/io.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/linear_solver.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/smoothing.h"

using namespace geotex;

namespace {
// Subdivided cubes of about 10^4, 10^5, 10^6 faces (12 n^2), with noise so the Laplacian is irregular.
const Mesh& cube_with_faces(int64_t target) {
  static std::map<int64_t, Mesh> cache;
  auto it = cache.find(target);
  if (it != cache.end()) return it->second;
  const int n = target >= 1000000 ? 289 : target >= 100000 ? 92 : 29;
  Mesh m = subdivided_cube(n);
  NoiseOptions o;
  o.sigma = 0.1;
  set_positions(m, add_noise(m, o));
  return cache.emplace(target, std::move(m)).first->second;
}

std::filesystem::path scratch(const char* name) {
  return std::filesystem::temp_directory_path() / (std::string("geotex-bench-") + std::to_string(getpid()) + name);
}
}  // namespace

static void BM_PlyWriteBinary(benchmark::State& state) {
  const Mesh& m = cube_with_faces(state.range(0));
  const auto path = scratch(".ply");
  for (auto _ : state) write_mesh(m, path);
  state.counters["faces"] = static_cast<double>(m.n_faces());
  std::filesystem::remove(path);
}
BENCHMARK(BM_PlyWriteBinary)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(3);

static void BM_PlyReadBinary(benchmark::State& state) {
  const Mesh& m = cube_with_faces(state.range(0));
  const auto path = scratch("-r.ply");
  write_mesh(m, path);
  for (auto _ : state) benchmark::DoNotOptimize(read_mesh(path));
  state.counters["faces"] = static_cast<double>(m.n_faces());
  std::filesystem::remove(path);
}
BENCHMARK(BM_PlyReadBinary)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(3);

static void BM_CotanLaplacian(benchmark::State& state) {
  const Mesh& m = cube_with_faces(state.range(0));
  for (auto _ : state) {
    SparseMatrix C = cotan_matrix(m);
    Eigen::VectorXd M = mass_diagonal(m);
    benchmark::DoNotOptimize(C);
    benchmark::DoNotOptimize(M);
  }
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_CotanLaplacian)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(3);

static void BM_ImplicitCotanStep(benchmark::State& state) {
  const Mesh& m = cube_with_faces(state.range(0));
  SmoothingOptions o;
  o.lambda = 1.0;
  for (auto _ : state) benchmark::DoNotOptimize(smooth(m, o));
  state.counters["faces"] = static_cast<double>(m.n_faces());
  state.SetLabel(SpdSolver::backend());
}
BENCHMARK(BM_ImplicitCotanStep)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(3);

static void BM_ImplicitUmbrellaStep(benchmark::State& state) {
  const Mesh& m = cube_with_faces(state.range(0));
  SmoothingOptions o;
  o.laplacian = LaplacianType::Umbrella;
  for (auto _ : state) benchmark::DoNotOptimize(smooth(m, o));
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_ImplicitUmbrellaStep)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK_MAIN();
