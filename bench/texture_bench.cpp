// Height-and-tilt texture: extraction + reconstruction at ~10^5 and ~10^6 vertices with both tilt
// solvers; 1-form least-squares fit at 10^5 and 10^6 faces.
// Run: build-texture/bench/texture_bench --benchmark_filter=Texture   (one iteration each)

#include <benchmark/benchmark.h>

#include <ctime>
#include <map>

#include "geotex/core/geometry.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/tools/shapes.h"
#include "geotex/texture/texture.h"

using namespace geotex;

namespace {

TexturedShape spikes_on(const Mesh& base) {
  SpikeOptions o;
  o.count = 200;
  return spiky(base, o);
}

// Spiky sphere on icosphere(level): level 7 ≈ 164k vertices, level 8 ≈ 655k.
const TexturedShape& ico_shape(int level) {
  static std::map<int, TexturedShape> cache;
  auto it = cache.find(level);
  if (it == cache.end()) it = cache.emplace(level, spikes_on(icosphere(level))).first;
  return it->second;
}

// Spiky sphere on a cube grid pushed onto the unit sphere: 6n² + 2 vertices (n = 129: 99 848,
// n = 408: 998 786), to measure at the 10^5 and 10^6 vertices.
const TexturedShape& cube_sphere_shape(int n) {
  static std::map<int, TexturedShape> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    Mesh m = subdivided_cube(n, 2.0);
    MatrixX3d X = positions(m);
    X.rowwise().normalize();
    set_positions(m, X);
    it = cache.emplace(n, spikes_on(m)).first;
  }
  return it->second;
}

void run(benchmark::State& state, const TexturedShape& s) {
  TextureOptions opt;
  opt.solver = state.range(1) ? TiltSolver::Direct : TiltSolver::Iterative;
  const MatrixX3d X = positions(s.textured);
  double err = 0;
  TiltFitReport fit;
  const std::clock_t cpu0 = std::clock();  // process CPU time, all threads (Google Benchmark's is the main thread's)
  for (auto _ : state) {
    TextureCodec codec(s.base, opt);
    const Texture tex = codec.extract(X);
    const MatrixX3d Y = codec.apply(tex);
    err = (Y - X).rowwise().norm().maxCoeff();
    fit = codec.last_fit();
    benchmark::DoNotOptimize(Y.data());
  }
  state.counters["process_cpu_s"] = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  state.counters["vertices"] = static_cast<double>(s.base.n_vertices());
  state.counters["max_err_per_edge"] = err / mean_edge_length(s.base);
  state.counters["cgls_iterations"] = fit.iterations;
  state.counters["iterative_used"] = fit.iterative;
  state.SetLabel(state.range(1) ? "direct" : "iterative");
}

// Argument 1: 0 = iterative (default), 1 = direct.
void BM_TextureExtractReconstruct(benchmark::State& state) { run(state, ico_shape(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_TextureExtractReconstruct)
    ->Args({7, 0})->Args({8, 0})->Args({7, 1})->Args({8, 1})
    ->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_TextureCubeSphere(benchmark::State& state) { run(state, cube_sphere_shape(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_TextureCubeSphere)
    ->Args({129, 0})->Args({408, 0})->Args({129, 1})->Args({408, 1})
    ->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_OneFormFit(benchmark::State& state) {
  const Mesh m = icosphere(static_cast<int>(state.range(0)));
  MatrixX3d T(m.n_vertices(), 3);
  const MatrixX3d V = positions(m);
  for (Eigen::Index i = 0; i < V.rows(); ++i) T.row(i) = Vec3(0, 0, 1).cross(Vec3(V.row(i).transpose())).transpose();
  double err = 0;
  for (auto _ : state) {
    OneFormFitter fitter(m);
    const Eigen::VectorXd c = fitter.fit(T);
    err = (one_form_to_vertices(m, c) - T).rowwise().norm().maxCoeff();
  }
  state.counters["faces"] = static_cast<double>(m.n_faces());
  state.counters["max_err"] = err;
}
BENCHMARK(BM_OneFormFit)->Arg(6)->Arg(8)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
