// Time to convergence of MRF denoising (thesis ch. 6) with the deterministic vertex optimizer:
// Fandisk0.3 of the shared data, and a noisy subdivided cube of about 10^6 faces.
//
//   cmake -S . -B build -DGEOTEX_BUILD_BENCH=ON && cmake --build build --target mrf_bench
//   build/bench/mrf_bench --benchmark_filter=Fandisk
//   build/bench/mrf_bench --benchmark_filter=Million

#include <filesystem>

#include <benchmark/benchmark.h>

#include "geotex/core/io.h"
#include "geotex/tools/metrics.h"
#include "geotex/denoise/mrf.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

void run(benchmark::State& state, const Mesh& noisy, const Mesh* truth, MrfOptimizer optimizer) {
  MrfOptions o;
  o.optimizer = optimizer;
  MrfResult r;
  for (auto _ : state) r = mrf_denoise(noisy, o);
  state.counters["faces"] = static_cast<double>(noisy.n_faces());
  state.counters["iterations"] = r.iterations;
  int labelled = 0;
  for (Eigen::Index e = 0; e < r.edge_labels.size(); ++e) labelled += r.edge_labels[e] > 0.5;
  state.counters["labelled"] = labelled;
  if (truth) {
    Mesh out = noisy;
    set_positions(out, r.positions);
    state.counters["normal_error_deg"] = compare_meshes(out, *truth).mean_normal_error_deg;
  }
}

void BM_MrfFandisk(benchmark::State& state) {
  const auto dir = std::filesystem::path(GEOTEX_DATA_DIR) / "denoise" / "Fandisk0.3";
  if (!std::filesystem::exists(dir / "Noisy.obj")) {
    state.SkipWithError("shared data not found");
    return;
  }
  const Mesh noisy = read_mesh((dir / "Noisy.obj").string());
  const Mesh truth = read_mesh((dir / "Original.obj").string());
  run(state, noisy, &truth, static_cast<MrfOptimizer>(state.range(0)));
}
BENCHMARK(BM_MrfFandisk)
    ->Arg(static_cast<int>(MrfOptimizer::Lbfgs))
    ->Arg(static_cast<int>(MrfOptimizer::Cg))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_MrfMillion(benchmark::State& state) {
  const Mesh clean = subdivided_cube(290);  // 1,009,200 faces
  Mesh noisy = clean;
  NoiseOptions n;
  n.sigma = 0.3;
  set_positions(noisy, add_noise(clean, n));
  run(state, noisy, &clean, MrfOptimizer::Lbfgs);
}
BENCHMARK(BM_MrfMillion)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
