// Height-and-tilt texture: extraction + reconstruction at ~10^5 and ~10^6 vertices; 1-form least-squares
// fit at 10^5 and 10^6 faces. Run: build-texture/bench/texture_bench --benchmark_min_time=1x

#include <benchmark/benchmark.h>

#include "geotex/geometry.h"
#include "geotex/one_form.h"
#include "geotex/shapes.h"
#include "geotex/texture.h"

using namespace geotex;

namespace {

// Spiky sphere on icosphere(level): level 7 ≈ 164k vertices, level 8 ≈ 655k, level 9 ≈ 2.6M.
const TexturedShape& shape(int level) {
  static std::map<int, TexturedShape> cache;
  auto it = cache.find(level);
  if (it == cache.end()) {
    SpikeOptions o;
    o.count = 200;
    it = cache.emplace(level, spiky(icosphere(level), o)).first;
  }
  return it->second;
}

void BM_TextureExtractReconstruct(benchmark::State& state) {
  const TexturedShape& s = shape(static_cast<int>(state.range(0)));
  const MatrixX3d X = positions(s.textured);
  double err = 0;
  for (auto _ : state) {
    TextureCodec codec(s.base);
    const Texture tex = codec.extract(X);
    const MatrixX3d Y = codec.apply(tex);
    err = (Y - X).rowwise().norm().maxCoeff();
    benchmark::DoNotOptimize(Y.data());
  }
  state.counters["vertices"] = static_cast<double>(s.base.n_vertices());
  state.counters["max_err_per_edge"] = err / mean_edge_length(s.base);
}
BENCHMARK(BM_TextureExtractReconstruct)->Arg(7)->Arg(8)->Unit(benchmark::kMillisecond)->Iterations(1);

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
