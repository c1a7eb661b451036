// Benchmarks of the toolkit: parametrization (Sec. 5.4), Laplacian editing (Sec. 5.1.4), ADF.
// Run: build/bench/edit_bench --benchmark_filter=... (results in bench/edit.md)

#include <map>

#include <benchmark/benchmark.h>

#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

// plane(n) has 2n² faces: n = 224 → 1.0e5, n = 708 → 1.0e6.
const Mesh& plate(int n) {
  static std::map<int, Mesh> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    Mesh m = plane(n, 2.0);
    MatrixX3d X = positions(m);
    X.col(2) = 0.3 * (X.col(0).array() * X.col(0).array() + X.col(1).array() * X.col(1).array());  // a curved cap
    set_positions(m, X);
    it = cache.emplace(n, std::move(m)).first;
  }
  return it->second;
}

void BM_Parametrize(benchmark::State& state) {
  const Mesh& m = plate(static_cast<int>(state.range(0)));
  const ParamMethod method = static_cast<ParamMethod>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(parametrize(m, {method}));
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_Parametrize)
    ->ArgsProduct({{224}, {0, 1, 3}})
    ->Args({708, 0})->Args({708, 3})
    ->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(2);

std::vector<int> handles_of(const Mesh& m) {
  const MatrixX3d X = positions(m);
  std::vector<int> h;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (X(i, 0) < -0.8 || X(i, 0) > 0.8) h.push_back(static_cast<int>(i));
  return h;
}

void BM_EditorFactor(benchmark::State& state) {
  const Mesh& m = plate(static_cast<int>(state.range(0)));
  const std::vector<int> h = handles_of(m);
  EditOptions o;
  o.method = static_cast<EditMethod>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(LaplacianEditor(m, h, {}, o));
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_EditorFactor)->ArgsProduct({{224}, {0, 1, 2}})->Args({708, 0})
    ->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(2);

void BM_EditorSolve(benchmark::State& state) {
  const Mesh& m = plate(static_cast<int>(state.range(0)));
  const std::vector<int> h = handles_of(m);
  EditOptions o;
  o.method = static_cast<EditMethod>(state.range(1));
  const LaplacianEditor ed(m, h, {}, o);
  const MatrixX3d X = positions(m);
  MatrixX3d C(h.size(), 3);
  for (size_t k = 0; k < h.size(); ++k) C.row(k) = X.row(h[k]) + Eigen::RowVector3d(0, 0, X(h[k], 0) > 0 ? 0.2 : 0);
  for (auto _ : state) benchmark::DoNotOptimize(ed.solve(C));
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_EditorSolve)->ArgsProduct({{224}, {0, 1, 2}})->Args({708, 0})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_Adf(benchmark::State& state) {
  const Mesh& m = plate(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(auto_diffusion_function(m, {0.1, static_cast<int>(state.range(1))}));
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_Adf)->Args({224, 50})->Args({224, 100})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
