// Timing of the picture and page writers: software rendering (rasterize + shade + anti-alias),
// PNG encoding, and viewer-page assembly, on generated spheres of growing size.
//   build-<you>/bench/render_bench --benchmark_min_time=0.5s

#include <benchmark/benchmark.h>

#include "geotex/tools/render.h"
#include "geotex/tools/shapes.h"
#include "geotex/tools/viewer.h"

using namespace geotex;

static void BM_RenderSphere(benchmark::State& state) {
  const Mesh m = icosphere(static_cast<int>(state.range(0)), 1.0);
  RenderOptions o;  // 800x600, 2x2 supersampling, smooth
  for (auto _ : state) benchmark::DoNotOptimize(render_mesh(m, o).covered_pixels);
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_RenderSphere)->Arg(3)->Arg(5)->Arg(7)->Unit(benchmark::kMillisecond);

static void BM_RenderFieldAndEdges(benchmark::State& state) {
  const Mesh m = icosphere(6, 1.0);
  RenderLayers l;
  l.field = positions(m).col(2);
  l.segments = edges(m).topRows(20000);
  for (auto _ : state) benchmark::DoNotOptimize(render_mesh(m, {}, l).covered_pixels);
  state.counters["faces"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_RenderFieldAndEdges)->Unit(benchmark::kMillisecond);

static void BM_EncodePng(benchmark::State& state) {
  const Image img = render_mesh(icosphere(5, 1.0), {}).image;  // 800x600
  size_t bytes = 0;
  for (auto _ : state) bytes = encode_png(img).size();
  state.counters["png_bytes"] = static_cast<double>(bytes);
  state.counters["raw_bytes"] = static_cast<double>(img.rgb.size());
}
BENCHMARK(BM_EncodePng)->Unit(benchmark::kMillisecond);

static void BM_ViewerPage(benchmark::State& state) {
  const Mesh m = icosphere(static_cast<int>(state.range(0)), 1.0);
  const std::string script(600000, 'x');  // stands in for the ~560 KiB bundle
  size_t bytes = 0;
  for (auto _ : state) bytes = viewer_page({{"m", m, {}}}, {}, script).size();
  state.counters["faces"] = static_cast<double>(m.n_faces());
  state.counters["page_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_ViewerPage)->Arg(5)->Arg(7)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
