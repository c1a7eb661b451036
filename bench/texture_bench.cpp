// Height-and-tilt texture: extraction + reconstruction at ~10^5 and ~10^6 vertices with both tilt
// solvers; 1-form least-squares fit at 10^5 and 10^6 faces; issue 17: re-applying after deformations,
// the base shape, transfer, whole-surface atlases and animation frames (figures in bench/texture.md).
// Run: build/bench/texture_bench --benchmark_filter=Texture   (one iteration each)

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/resize/resize.h"
#include "geotex/texture/measures.h"
#include "geotex/texture/texture.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/toolkit/space_maps.h"
#include "geotex/tools/shapes.h"

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

// ---------------------------------------------------------------------------------------------
// Issue 17

double process_cpu() { return double(std::clock()) / CLOCKS_PER_SEC; }  // all threads

int nearest(const Mesh& m, const Vec3& p) {
  Eigen::Index best;
  (positions(m).rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

std::filesystem::path data(const char* name) { return std::filesystem::path(GEOTEX_DATA_DIR) / name; }

// Tentacles re-applied on a deformed stick (level 1): worst of the nine, length |tip − foot| and lean =
// angle of tip − foot from the deformed base's normal at the foot. Args: deformation, encoding (0 lean, 1 thesis).
void BM_TextureDeform(benchmark::State& state) {
  static std::vector<Tentacle> info;
  static const TexturedShape s = tentacle_stick(1, &info);
  const std::vector<std::pair<const char*, SpaceMap>> maps = {
      {"x0.5 axis", scale_map(Vec3(0.5, 1, 1))},   {"x1.5 axis", scale_map(Vec3(1.5, 1, 1))},
      {"x2 axis", scale_map(Vec3(2, 1, 1))},       {"x0.5 uniform", scale_map(Vec3(0.5, 0.5, 0.5))},
      {"arc bend r4", arc_bend_map(4.0)},          {"shear bend k0.15", bend_map(0.15)},
      {"twist 90deg", twist_map(M_PI / 12)}};
  const auto& [name, map] = maps[state.range(0)];
  TextureOptions o;
  o.encoding = state.range(1) ? TiltEncoding::OneForm : TiltEncoding::Lean;
  const Texture tex = TextureCodec(s.base, o).extract(positions(s.textured));
  Mesh deformed = s.base;
  set_positions(deformed, apply_space_map(map, positions(s.base)));
  std::vector<int> feet;
  for (const auto& t : info) feet.push_back(t.foot);
  double length = 0, lean = 0;
  for (auto _ : state) {
    const std::vector<Protrusion> p = measure_protrusions(deformed, apply_texture(deformed, tex, o), feet);
    for (size_t k = 0; k < feet.size(); ++k) {
      length = std::max(length, std::abs(p[k].length / info[k].length - 1));
      lean = std::max(lean, std::abs(p[k].lean_deg - info[k].lean_deg));
    }
  }
  state.counters["length_change_pct"] = 100 * length;
  state.counters["lean_change_deg"] = lean;
  state.SetLabel(std::string(name) + (state.range(1) ? ", thesis 1-form" : ", lean encoding"));
}
BENCHMARK(BM_TextureDeform)->ArgsProduct({{0, 1, 2, 3, 4, 5, 6}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(1);

// Issue 26: the lean's angle and direction (azimuth) after a deformation of the base, for the lean
// encoding (default: the direction turned by the polar rotation of the base's tangent Jacobian), the
// push-forward (issue 17: J d), the thesis' 1-form, and a tangent-space vector displacement baseline: each
// displacement stored in the frame (e, n × e, n) at its vertex, e the tangent part of its first outgoing
// edge, and re-applied in the same frame of the deformed base. Azimuth = the angle between the tangential
// part of tip − foot and R l (l the original one, R the polar rotation of the map's tangent Jacobian at
// the foot, polar_rotated()). Worst of the stick's nine tentacles (level 1). Arg: deformation.
void BM_TextureAzimuth(benchmark::State& state) {
  static std::vector<Tentacle> info;
  static const TexturedShape s = tentacle_stick(1, &info);
  static const Texture tex = extract_texture(s.base, positions(s.textured));
  static const Texture thesis_tex = [] {
    TextureOptions o;
    o.encoding = TiltEncoding::OneForm;
    return extract_texture(s.base, positions(s.textured), o);
  }();
  const std::vector<std::pair<const char*, SpaceMap>> maps = {
      {"x2 axis", scale_map(Vec3(2, 1, 1))},
      {"x0.5 axis", scale_map(Vec3(0.5, 1, 1))},
      {"x2 uniform", scale_map(Vec3(2, 2, 2))},
      {"x0.5 uniform", scale_map(Vec3(0.5, 0.5, 0.5))},
      {"arc bend r4", arc_bend_map(4.0)},
      {"shear bend k0.15", bend_map(0.15)},
      {"shear x+=0.5z", [](const Vec3& x) { return Vec3(x.x() + 0.5 * x.z(), x.y(), x.z()); }},
      {"twist 90deg", twist_map(M_PI / 12)},
      {"twist 360deg", twist_map(M_PI / 3)}};
  const auto& [name, map] = maps[state.range(0)];
  const MatrixX3d B0 = positions(s.base), X0 = positions(s.textured);
  Mesh deformed = s.base;
  set_positions(deformed, apply_space_map(map, B0));
  const MatrixX3d B1 = positions(deformed);
  std::vector<int> feet;
  for (const auto& t : info) feet.push_back(t.foot);
  const std::vector<Protrusion> before = measure_protrusions(s.base, X0, feet);
  // The vector displacement baselines: each displacement in a frame (e1, n × e1, n) re-made on the
  // deformed base, e1 = the tangent part of (a) the vertex's first outgoing edge (any direction), or
  // (b) a UV tangent along the stick's axis: x at rest, J x after the map (J the map's Jacobian there),
  // as a texture-space tangent of a limb parametrized along its length is carried.
  const MatrixX3d N0 = vertex_normals(s.base, NormalWeighting::Angle), N1 = vertex_normals(deformed, NormalWeighting::Angle);
  auto vector_displacement = [&](bool uv) {
    MatrixX3d Y(B0.rows(), 3);
    for (auto v : s.base.vertices()) {
      const int i = v.idx(), j = s.base.to_vertex_handle(s.base.halfedge_handle(v)).idx();
      const Vec3 h0 = uv ? Vec3::UnitX() : Vec3((B0.row(j) - B0.row(i)).transpose());
      const Vec3 h1 = uv ? Vec3(space_map_jacobian(map, B0.row(i).transpose()) * Vec3::UnitX())
                         : Vec3((B1.row(j) - B1.row(i)).transpose());
      const Eigen::Matrix3d F0 = local_frame(N0.row(i).transpose(), h0), F1 = local_frame(N1.row(i).transpose(), h1);
      Y.row(i) = B1.row(i) + (F1 * (F0.transpose() * (X0.row(i) - B0.row(i)).transpose())).transpose();
    }
    return Y;
  };
  const MatrixX3d Yvec = vector_displacement(false), Yuv = vector_displacement(true);
  TextureOptions lean, push, thesis;
  push.encoding = TiltEncoding::LeanPushforward;
  thesis.encoding = TiltEncoding::OneForm;
  MatrixX3d Ylean, Ypush, Ythesis;
  const double cpu0 = process_cpu();
  for (auto _ : state) Ylean = apply_texture(deformed, tex, lean);
  state.counters["lean_apply_cpu_s"] = process_cpu() - cpu0;
  Ypush = apply_texture(deformed, tex, push);
  Ythesis = apply_texture(deformed, thesis_tex, thesis);
  auto worst = [&](const MatrixX3d& Y, const char* key) {
    const std::vector<Protrusion> now = measure_protrusions(deformed, Y, feet);
    double lean_change = 0, azimuth = 0;
    for (size_t k = 0; k < feet.size(); ++k) {
      const Vec3 x = B0.row(feet[k]).transpose();
      const Vec3 rl = polar_rotated(space_map_jacobian(map, x), before[k].normal, now[k].normal, before[k].direction);
      lean_change = std::max(lean_change, std::abs(now[k].lean_deg - before[k].lean_deg));
      azimuth = std::max(azimuth, std::acos(std::clamp(now[k].direction.dot(rl.normalized()), -1.0, 1.0)) * 180 / M_PI);
    }
    state.counters[std::string(key) + "_lean_deg"] = lean_change;
    state.counters[std::string(key) + "_azimuth_deg"] = azimuth;
  };
  worst(Ylean, "lean");
  worst(Ypush, "push");
  worst(Ythesis, "thesis");
  worst(Yvec, "vector");
  worst(Yuv, "vector_uv");
  state.SetLabel(name);
}
BENCHMARK(BM_TextureAzimuth)->DenseRange(0, 8)->Unit(benchmark::kMillisecond)->Iterations(1);

// Base shape. Args: mesh (0 igea, 1 tentacle stick level 1), method (0 robust, 1 thesis smoothing).
void BM_TextureBaseShape(benchmark::State& state) {
  std::vector<Tentacle> info;
  Mesh m;
  TexturedShape stick;
  if (state.range(0) == 0) {
    if (!std::filesystem::exists(data("igea.ply"))) return state.SkipWithError("no shared data");
    m = read_mesh(data("igea.ply"));
  } else {
    stick = tentacle_stick(1, &info);
    m = stick.textured;
  }
  BaseShapeOptions o;
  if (state.range(1)) BaseShapeOptions::table().apply_preset(o, "thesis");
  BaseShape b;
  const double cpu0 = process_cpu();
  for (auto _ : state) b = base_shape(m, o);
  state.counters["process_cpu_s"] = process_cpu() - cpu0;
  state.counters["median_off_normal_deg"] = b.median_off_normal_deg;
  state.counters["vertices"] = static_cast<double>(m.n_vertices());
  state.counters["unfolded"] = static_cast<double>(b.unfolded);
  if (!info.empty()) {
    const MatrixX3d X = positions(m);
    double ratio = 1e9;
    for (const auto& t : info) ratio = std::min(ratio, (X.row(t.foot) - b.positions.row(t.foot)).norm() / t.length);
    state.counters["min_tip_over_length"] = ratio;
  }
  state.SetLabel(std::string(state.range(0) ? "tentacle stick L1" : "igea") + (state.range(1) ? ", thesis" : ", robust"));
}
BENCHMARK(BM_TextureBaseShape)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(1);

struct TransferSource {
  Mesh base;
  Texture texture;
  int center = 0;
  double radius = 0;
  bool ok = true;
};
const TransferSource& transfer_source(int which) {
  static std::map<int, TransferSource> cache;
  auto it = cache.find(which);
  if (it != cache.end()) return it->second;
  TransferSource s;
  if (which == 0) {  // the tentacle plate (level 1), its middle tentacle at the centre
    const TexturedShape p = tentacle_plane(1);
    s.base = p.base;
    s.texture = extract_texture(p.base, positions(p.textured));
    s.center = nearest(s.base, Vec3(0, 0, 0));
    s.radius = 1.0;
  } else if (!std::filesystem::exists(data("igea.ply"))) {
    s.ok = false;
  } else {  // igea: a patch of hair, about 25 mean edges across
    const Mesh ig = read_mesh(data("igea.ply"));
    s.base = ig;
    set_positions(s.base, extract_base_shape(ig));
    s.texture = extract_texture(s.base, positions(ig));
    s.center = nearest(s.base, Vec3(0, 0.02, 0.04));
    s.radius = 0.012;
  }
  return cache.emplace(which, std::move(s)).first->second;
}
// Targets: 0 icosphere(5) radius 1, 1 spot, 2 icosphere(2) (162 vertices).
bool transfer_target(int which, Mesh& m, Vec3& at, double& radius) {
  if (which == 1) {
    if (!std::filesystem::exists(data("spot.obj"))) return false;
    m = read_mesh(data("spot.obj"));
    at = Vec3(0.45, 0, 0);
    radius = 0.3;
  } else {
    m = icosphere(which == 0 ? 5 : 2, 1.0);
    at = Vec3(0, 0, 1);
    radius = 0.6;
  }
  return true;
}

// One disk. Args: source (0 tentacle plate, 1 igea), target (0 sphere, 1 spot, 2 coarse icosphere(2)).
void BM_TextureTransfer(benchmark::State& state) {
  const TransferSource& s = transfer_source(static_cast<int>(state.range(0)));
  Mesh target;
  Vec3 at;
  double radius = 0;
  if (!s.ok || !transfer_target(static_cast<int>(state.range(1)), target, at, radius))
    return state.SkipWithError("no shared data");
  TransferOptions o;
  o.source_center = s.center;
  o.source_radius = s.radius;
  o.target_center = nearest(target, at);
  o.target_radius = radius;
  TransferResult r;
  const double cpu0 = process_cpu();
  for (auto _ : state) r = transfer_texture(s.base, s.texture, target, o);
  state.counters["process_cpu_s"] = process_cpu() - cpu0;
  const TransferQuality q = transfer_quality(s.base, s.texture, r, o);
  state.counters["disk_mean_pct"] = 100 * q.mean_change;
  state.counters["disk_rms_pct"] = 100 * q.rms_change;
  state.counters["surface_mean_pct"] = 100 * q.surface_mean_change;
  state.counters["surface_rms_pct"] = 100 * q.surface_rms_change;
  state.counters["lean_deg"] = q.lean_change_deg;
  state.counters["folded"] = static_cast<double>(q.folded);
  state.counters["falloff_step_pct"] = 100 * q.falloff_step;
  state.counters["rim_cliff"] = q.rim_cliff;
  state.counters["added_vertices"] = static_cast<double>(r.added_vertices);
  state.counters["warnings"] = static_cast<double>(r.warnings.size());
  state.counters["damage_folded"] = static_cast<double>(r.damage.folded);
  state.counters["damage_self_intersecting"] = static_cast<double>(r.damage.self_intersecting);
  state.counters["base_folded"] = static_cast<double>(r.damage.base_folded);
  state.counters["base_self_intersecting"] = static_cast<double>(r.damage.base_self_intersecting);
  static const char* sources[] = {"tentacle plate", "igea"};
  static const char* targets[] = {"icosphere(5)", "spot", "icosphere(2)"};
  state.SetLabel(std::string(sources[state.range(0)]) + " -> " + targets[state.range(1)]);
}
BENCHMARK(BM_TextureTransfer)->ArgsProduct({{0, 1}, {0, 1, 2}})->Unit(benchmark::kMillisecond)->Iterations(1);

// Whole surface. Args: source (0 tentacle plate, 1 igea), target (0 icosphere(4), 1 spot).
void BM_TextureAtlas(benchmark::State& state) {
  const TransferSource& s = transfer_source(static_cast<int>(state.range(0)));
  Mesh target;
  if (!s.ok) return state.SkipWithError("no shared data");
  if (state.range(1) == 0) {
    target = icosphere(4, 1.0);
  } else {
    if (!std::filesystem::exists(data("spot.obj"))) return state.SkipWithError("no shared data");
    target = read_mesh(data("spot.obj"));
  }
  AtlasOptions o;
  o.source_center = s.center;
  o.source_radius = s.radius;
  o.target_radius = state.range(1) == 0 ? 0.5 : 0.25;
  AtlasResult r;
  const double cpu0 = process_cpu();
  for (auto _ : state) r = cover_with_texture(s.base, s.texture, target, o);
  state.counters["process_cpu_s"] = process_cpu() - cpu0;
  const SeamQuality q = atlas_seams(r);
  state.counters["disks"] = static_cast<double>(r.centers.size());
  state.counters["vertices"] = static_cast<double>(r.target.n_vertices());
  state.counters["min_coverage"] = r.coverage.minCoeff();
  state.counters["across_p99"] = q.across99;
  state.counters["within_p99"] = q.within99;
  state.counters["across_max"] = q.across_max;
  state.counters["within_max"] = q.within_max;
  Mesh textured = r.target;
  set_positions(textured, apply_texture(r.target, r.texture));
  state.counters["folded"] = static_cast<double>(folded_faces(textured));
  state.counters["damage_folded"] = static_cast<double>(r.damage.folded);
  state.counters["damage_self_intersecting"] = static_cast<double>(r.damage.self_intersecting);
  state.counters["base_folded"] = static_cast<double>(r.damage.base_folded);
  state.counters["base_self_intersecting"] = static_cast<double>(r.damage.base_self_intersecting);
  static const char* sources[] = {"tentacle plate", "igea"};
  state.SetLabel(std::string(sources[state.range(0)]) + (state.range(1) ? " over spot" : " over icosphere(4)"));
}
BENCHMARK(BM_TextureAtlas)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(1);

// Animation frames on the tentacle plate, level 2 (66 049 vertices): the factorization happens once,
// outside the timed loop (counter setup_cpu_s); each iteration is one wiggle frame. Arg: refit (1) or
// displace directly (0).
void BM_TextureAnimateFrame(benchmark::State& state) {
  static const TexturedShape p = tentacle_plane(2);
  static const Texture tex = extract_texture(p.base, positions(p.textured));
  AnimationOptions o;
  o.refit = state.range(0) != 0;
  const double cpu0 = process_cpu();
  TextureAnimator animator(p.base, tex, o);
  benchmark::DoNotOptimize(animator.positions(0).data());  // the first frame factors the tilt system
  state.counters["setup_cpu_s"] = process_cpu() - cpu0;
  int k = 1;
  const double cpu1 = process_cpu();
  for (auto _ : state) {
    const MatrixX3d X = animator.positions(k++ % o.frames);
    benchmark::DoNotOptimize(X.data());
  }
  state.counters["process_cpu_per_frame_s"] = (process_cpu() - cpu1) / state.iterations();
  state.counters["vertices"] = static_cast<double>(p.base.n_vertices());
  state.SetLabel(o.refit ? "refit each frame" : "displace directly");
}
BENCHMARK(BM_TextureAnimateFrame)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(24);

}  // namespace

BENCHMARK_MAIN();
