// Phong-normal projection: analytic cubic vs Newton — time per query and how often each finds the wrong
// or no solution on random configurations. Run: build-texture/bench/projection_bench

#include <benchmark/benchmark.h>

#include <vector>

#include "geotex/toolkit/phong_projection.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

struct Config {
  PhongTriangle t;
  Vec3 p;
};

// Random triangles with vertex normals tilted up to `spread` from +z and points within ±0.75 of the plane.
const std::vector<Config>& configs(double spread) {
  static std::map<double, std::vector<Config>> cache;
  auto it = cache.find(spread);
  if (it != cache.end()) return it->second;
  Rng rng(42);
  std::vector<Config> out;
  auto unit = [&] { return Vec3(rng.normal(), rng.normal(), rng.normal()).normalized(); };
  for (int i = 0; i < 100000; ++i) {
    auto n = [&] { return (Vec3(0, 0, 1) + spread * unit()).normalized(); };
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.3, 0.9, 0);
    // p above a point inside the triangle, so an inside solution usually exists.
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1) { u = 1 - u; v = 1 - v; }
    const Vec3 q = u * a + v * b + (1 - u - v) * c;
    out.push_back({PhongTriangle(a, b, c, n(), n(), n()), q + Vec3(0, 0, (rng.uniform() - 0.5) * 1.5)});
  }
  return cache.emplace(spread, std::move(out)).first->second;
}

void BM_Analytic(benchmark::State& state) {
  const auto& cs = configs(state.range(0) / 10.0);
  size_t k = 0, none = 0, n = 0;
  for (auto _ : state) {
    const Config& c = cs[k++ % cs.size()];
    const auto cands = phong_project_analytic(c.p, c.t);
    bool inside = false;
    for (const auto& x : cands) inside |= x.inside;
    none += !inside;
    ++n;
    benchmark::DoNotOptimize(cands.data());
  }
  state.counters["no_inside_solution_rate"] = double(none) / n;
}
BENCHMARK(BM_Analytic)->Arg(3)->Arg(8);

void BM_Newton(benchmark::State& state) {
  const auto& cs = configs(state.range(0) / 10.0);
  size_t k = 0, failed = 0, wrong = 0, n = 0;
  for (auto _ : state) {
    const Config& c = cs[k++ % cs.size()];
    const PhongNewtonResult r = phong_project_newton(c.p, c.t);
    benchmark::DoNotOptimize(r);
    ++n;
    if (!r.converged) ++failed;
  }
  // Quality, outside the timed loop: Newton ends outside (or nowhere) although an inside solution exists.
  for (const Config& c : cs) {
    const auto cands = phong_project_analytic(c.p, c.t);
    bool inside = false;
    for (const auto& x : cands) inside |= x.inside;
    if (!inside) continue;
    const PhongNewtonResult r = phong_project_newton(c.p, c.t);
    if (!r.converged || !r.candidate.inside) ++wrong;
  }
  state.counters["not_converged_rate"] = double(failed) / n;
  state.counters["wrong_or_none_rate"] = double(wrong) / cs.size();
}
BENCHMARK(BM_Newton)->Arg(3)->Arg(8);

void BM_MeshProjection(benchmark::State& state) {
  const TexturedShape s = make_shape("spiky-sphere", 2);
  const PhongProjector proj(s.base);
  const MatrixX3d P = positions(s.textured);
  size_t k = 0, found = 0, n = 0;
  for (auto _ : state) {
    const PhongHit h = proj.project(Vec3(P.row(k++ % P.rows()).transpose()));
    found += h.found;
    ++n;
  }
  state.counters["found_rate"] = double(found) / n;
}
BENCHMARK(BM_MeshProjection);

// Points 1e7 away from a unit sphere (the sphere's own vertices scaled by 1e7): every face's box is
// about equally near, so the nearest-first search alone would solve every face for every point; the
// cones of vertex normals leave only the faces facing the point.
void BM_MeshProjectionFar(benchmark::State& state) {
  const Mesh s = icosphere(4, 1.0);
  const PhongProjector proj(s);
  const MatrixX3d P = 1e7 * positions(s);
  size_t k = 0, found = 0, n = 0;
  for (auto _ : state) {
    const PhongHit h = proj.project(Vec3(P.row(k++ % P.rows()).transpose()));
    found += h.found;
    ++n;
  }
  state.counters["found_rate"] = double(found) / n;
}
BENCHMARK(BM_MeshProjectionFar);

}  // namespace

BENCHMARK_MAIN();
