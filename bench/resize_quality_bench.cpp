// What feature-aware resizing must show (issue 18), measured: the tentacle stick scaled ×2 along its
// axis and bent into an arc (tentacle length and angle to the local base, feature map IoU), and real
// models scaled by (2, 1, 1) (box, marked share, feature aspect, creases at feature rims). Quality
// figures are counters; the times include the feature map. Results in bench/resize.md.
//   build/bench/resize_quality_bench                      (everything; the real models need ../shared/data)
//   build/bench/resize_quality_bench --benchmark_filter=Stick

#include <filesystem>
#include <map>

#include <benchmark/benchmark.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/resize/resize.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

double iou(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double inter = 0, uni = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    inter += std::min(a[i], b[i]);
    uni += std::max(a[i], b[i]);
  }
  return uni > 0 ? inter / uni : 0.0;
}

// Stick (level from the first argument) ×2 + arc of radius 6; the second argument picks the map
// (0 auto, 1 adf, 2 true tentacles) and the third the method (0 sliding, 1 thesis preset, 2 thesis
// preset with T_i rotations, 3 plain map).
void BM_Stick(benchmark::State& state) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(static_cast<int>(state.range(0)), &info);
  const Mesh& m = s.textured;
  const MatrixX3d X = positions(m);
  const double radius = TentacleOptions{}.radius;
  const Eigen::VectorXd truth = tentacle_truth(s.base, info, radius);
  SpaceMapOptions so;
  so.scale = Vec3(2, 1, 1);
  so.arc_radius = 6;
  const MatrixX3d C = apply_space_map(space_map(so, bounding_box(m)), X);
  ResizeOptions o;
  o.method = ResizeMethod::Sliding;  // the binary maps' method (the default, similarity, is for continuous maps)
  if (state.range(2) == 1 || state.range(2) == 2) ResizeOptions::table().apply_preset(o, "thesis");
  if (state.range(2) == 2) o.keep_feature_size = true;
  Eigen::VectorXd f;
  MatrixX3d Y;
  for (auto _ : state) {
    if (state.range(1) == 2) {
      f = truth;
    } else {
      FeatureMapOptions fo;
      fo.method = state.range(1) == 0 ? FeatureMapMethod::Auto : FeatureMapMethod::Adf;
      f = feature_map(m, fo).weights;
    }
    Y = state.range(2) == 3 ? C : feature_aware_resize(m, C, f, o);
  }
  double length = 0, angle = 0;
  for (const Tentacle& t : info) {
    const Eigen::VectorXd foot = tentacle_truth(s.base, {t}, radius);
    const ProtrusionPose a = measure_protrusion(m, X, t.foot, foot), b = measure_protrusion(m, Y, t.foot, foot);
    length = std::max(length, std::abs(b.length / a.length - 1));
    angle = std::max(angle, std::abs(b.angle_deg - a.angle_deg));
  }
  state.counters["vertices"] = static_cast<double>(m.n_vertices());
  state.counters["IoU"] = iou(f, truth);
  state.counters["worst_length_change_pct"] = 100 * length;
  state.counters["worst_angle_change_deg"] = angle;
  state.counters["rim_crease_deg"] = rim_crease_deg(m, Y, f);
  state.counters["input_rim_crease_deg"] = rim_crease_deg(m, X, f);
}
BENCHMARK(BM_Stick)->ArgsProduct({{0, 1}, {0, 1, 2}, {0, 1, 2, 3}})->Unit(benchmark::kMillisecond)->Iterations(1);

// A real model scaled by (2, 1, 1) with automatic features and the sliding method (second argument
// 0) or the thesis preset (1). Aspect: per connected feature region of at least 20 vertices, the
// change of the ratios of its principal extents (area-weighted PCA of its vertices), worst over regions.
const char* const kModels[] = {"cow.obj", "spot.obj", "igea.ply", "cheburashka.obj", "stanford-bunny.obj"};

void BM_Model(benchmark::State& state) {
  const std::filesystem::path path = std::filesystem::path(GEOTEX_DATA_DIR) / kModels[state.range(0)];
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("shared data not found");
    return;
  }
  const Mesh m = read_mesh(path);
  const MatrixX3d X = positions(m);
  const BoundingBox box = bounding_box(m);
  const MatrixX3d C = apply_space_map(scale_map({2, 1, 1}, box.center()), X);
  ResizeOptions o;
  o.method = ResizeMethod::Sliding;  // with the binary map "auto", as measured for issue 18
  if (state.range(1) == 1) ResizeOptions::table().apply_preset(o, "thesis");
  FeatureMapOptions binary;
  binary.method = FeatureMapMethod::Auto;
  FeatureMap fm;
  MatrixX3d Y;
  for (auto _ : state) {
    fm = feature_map(m, binary);
    Y = feature_aware_resize(m, C, fm.weights, o);
  }
  const Vec3 ratio = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose().cwiseQuotient(box.size());
  const auto before = region_extents(m, X, fm.weights), after = region_extents(m, Y, fm.weights),
             plain = region_extents(m, C, fm.weights);
  double worst = 0, worst_plain = 0;
  for (size_t k = 0; k < before.size(); ++k)
    if (before[k].vertices.size() >= 20) {
      worst = std::max(worst, aspect_change(before[k].extents, after[k].extents));
      worst_plain = std::max(worst_plain, aspect_change(before[k].extents, plain[k].extents));
    }
  state.SetLabel(kModels[state.range(0)]);
  state.counters["vertices"] = static_cast<double>(m.n_vertices());
  state.counters["marked_pct"] = 100 * fm.summary.marked_fraction;
  state.counters["regions"] = fm.summary.regions;
  state.counters["box_x"] = ratio.x();
  state.counters["box_y"] = ratio.y();
  state.counters["box_z"] = ratio.z();
  state.counters["worst_aspect_change_pct"] = 100 * worst;
  state.counters["plain_aspect_change_pct"] = 100 * worst_plain;
  state.counters["crease_q99_deg"] = rim_crease_deg(m, Y, fm.weights, 2, 0.99);
  state.counters["plain_crease_q99_deg"] = rim_crease_deg(m, C, fm.weights, 2, 0.99);
  state.counters["input_crease_q99_deg"] = rim_crease_deg(m, X, fm.weights, 2, 0.99);
}
BENCHMARK(BM_Model)->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
