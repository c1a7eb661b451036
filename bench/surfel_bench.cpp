// Surfel reconstruction at scale: subdivided_cube(n) with noise 0.3, the thesis parameters, 15 ICM sweeps
// (the thesis' million-face run, Fig. 7.7), then dual-mesh retrieval.
//   surfel_bench --benchmark_filter=Optimize/290   (1,009,200 faces)

#include <benchmark/benchmark.h>

#include "geotex/core/geometry.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/denoise/surfel.h"

using namespace geotex;

namespace {

struct Input {
  Mesh mesh;
  MatrixX3d X;
};

Input make_input(int n) {
  Input in{subdivided_cube(n), {}};
  NoiseOptions no;
  no.sigma = 0.3;
  in.X = add_noise(in.mesh, no);
  set_positions(in.mesh, in.X);
  return in;
}

void Optimize(benchmark::State& state) {
  const Input in = make_input(static_cast<int>(state.range(0)));
  const Neighborhoods N = one_ring_neighborhoods(in.mesh);
  const Surfels S0 = initial_surfels(in.mesh);
  SurfelOptions o;
  o.iterations = 15;
  o.unit_length = mean_edge_length(in.mesh);
  for (auto _ : state) benchmark::DoNotOptimize(optimize_surfels(in.X, N, S0, o));
  state.counters["faces"] = static_cast<double>(in.mesh.n_faces());
  state.counters["vertices"] = static_cast<double>(in.mesh.n_vertices());
}
BENCHMARK(Optimize)->Arg(50)->Arg(290)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void DualRetrieval(benchmark::State& state) {
  const Input in = make_input(static_cast<int>(state.range(0)));
  const Surfels S0 = initial_surfels(in.mesh);
  for (auto _ : state) benchmark::DoNotOptimize(triangulate_polygons(surfel_dual_polygons(in.mesh, in.X, S0)));
  state.counters["faces"] = static_cast<double>(in.mesh.n_faces());
}
BENCHMARK(DualRetrieval)->Arg(50)->Arg(290)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
