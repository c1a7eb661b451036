// Benchmarks of feature-aware resizing (thesis ch. 9) on the bumpy plate at 1e5 and 1e6 faces,
// including every factorization. Run: build/bench/resize_bench (results in bench/resize.md)

#include <array>
#include <map>

#include <benchmark/benchmark.h>

#include "geotex/resize/resize.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

// bumpy_plate(n) has 2n² faces: n = 224 → 1.0e5, n = 708 → 1.0e6.
const BumpyPlate& plate(int n) {
  static std::map<int, BumpyPlate> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, bumpy_plate({.n = n})).first;
  return it->second;
}

void BM_Resize(benchmark::State& state) {
  const BumpyPlate& b = plate(static_cast<int>(state.range(0)));
  ResizeOptions o;
  o.method = static_cast<ResizeMethod>(state.range(1));
  const SpaceMap map = scale_map({2, 1, 1});
  for (auto _ : state) benchmark::DoNotOptimize(feature_aware_resize(b.mesh, map, b.truth, o));
  state.counters["faces"] = static_cast<double>(b.mesh.n_faces());
}
// method 0 = Sliding (default), 1 = Thesis.
BENCHMARK(BM_Resize)->ArgsProduct({{224, 708}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(1);

// Feature maps (feature_map.h): method 0 = auto (the ADF's eigenproblem, then, on this plate, the
// height map it falls back to), 1 = height, 2 = adf.
void BM_FeatureMap(benchmark::State& state) {
  const BumpyPlate& b = plate(static_cast<int>(state.range(0)));
  FeatureMapOptions o;
  o.method = std::array{FeatureMapMethod::Auto, FeatureMapMethod::Height, FeatureMapMethod::Adf}[state.range(1)];
  for (auto _ : state) benchmark::DoNotOptimize(feature_map(b.mesh, o));
  state.counters["faces"] = static_cast<double>(b.mesh.n_faces());
}
BENCHMARK(BM_FeatureMap)->ArgsProduct({{224, 708}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
