// Denoising experiments and measurements (bench/denoise.md): runs the library's denoisers with options
// given by name (from their option tables, as the CLI and Python will), scores them against a truth,
// and measures CPU time of the library call alone.
//
//   denoise_bench run METHOD IN [--out OUT] [--edges E.ply] [--truth T] [--preset P] [name=value ...]
//       METHOD: mrf | mrf-normal | surfel
//   denoise_bench fan VALENCE                 the valence test: one vertex of the given valence
//
// Output: one line "key value ..." per run (normal error, Ev, label precision/recall, CPU seconds).

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/options.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/surfel.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }
double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Options from "name=value" arguments through the option table, after an optional preset.
template <class O>
O parse_options(const std::vector<std::string>& args, const std::string& preset) {
  O o;
  if (!preset.empty()) O::table().apply_preset(o, preset);
  for (const std::string& a : args) {
    const auto eq = a.find('=');
    if (eq == std::string::npos) throw InvalidOption("expected name=value, got '" + a + "'");
    const std::string name = a.substr(0, eq);
    const auto* f = O::table().find(name);
    if (!f) throw InvalidOption("unknown option '" + name + "'");
    f->set(o, parse_option_value(f->info, a.substr(eq + 1)));
  }
  return o;
}

template <class O>
std::string describe(const O& o) {
  std::string s;
  for (const auto& [name, v] : O::table().values(o)) s += fmt::format(" {}={}", name, format_option_value(v));
  return s;
}

struct Outcome {
  Mesh mesh;
  Eigen::VectorXd labels;
  double cpu = 0, wall = 0;
  std::string params;
};

// Truth's sharp edges (dihedral angle above 30°, as `geotex compare --labels`) and the labelled ones.
LabelScore label_score(const Mesh& result, const Eigen::VectorXd& labels, const Mesh& truth) {
  const Eigen::VectorXd D = dihedral_angles(truth);
  const MatrixX2i E = edges(truth), R = edges(result);
  std::vector<int> sharp, kept;
  for (Eigen::Index i = 0; i < D.size(); ++i)
    if (std::abs(D[i]) > 30.0 * M_PI / 180.0) sharp.push_back(static_cast<int>(i));
  for (Eigen::Index i = 0; i < labels.size(); ++i)
    if (labels[i] > 0.5) kept.push_back(static_cast<int>(i));
  MatrixX2i T(sharp.size(), 2), L(kept.size(), 2);
  for (size_t k = 0; k < sharp.size(); ++k) T.row(k) = E.row(sharp[k]);
  for (size_t k = 0; k < kept.size(); ++k) L.row(k) = R.row(kept[k]);
  return score_edge_labels(L, T);
}

Outcome run_method(const std::string& method, const Mesh& in, const std::vector<std::string>& args,
                   const std::string& preset) {
  Outcome out;
  const double c0 = cpu_seconds(), w0 = wall_seconds();
  if (method == "mrf" || method == "mrf-normal") {
    MrfResult r;
    if (method == "mrf") {
      const auto o = parse_options<MrfOptions>(args, preset);
      out.params = describe(o);
      r = mrf_denoise(in, o);
    } else {
      const auto o = parse_options<MrfNormalOptions>(args, preset);
      out.params = describe(o);
      r = mrf_normal_denoise(in, o);
    }
    out.mesh = in;
    set_positions(out.mesh, r.positions);
    out.labels = r.edge_labels;
  } else if (method == "surfel") {
    const auto o = parse_options<SurfelDenoiseOptions>(args, preset);
    out.params = describe(o);
    SurfelDenoiseResult r = surfel_denoise(in, o);
    out.mesh = std::move(r.mesh);
    out.labels = r.edge_labels;
  } else {
    throw InvalidOption("unknown method '" + method + "'");
  }
  out.cpu = cpu_seconds() - c0;
  out.wall = wall_seconds() - w0;
  return out;
}

int cmd_run(int argc, char** argv) {
  if (argc < 4) throw InvalidOption("usage: denoise_bench run METHOD IN [--out OUT] [--edges E] [--truth T] [--preset P] [k=v ...]");
  const std::string method = argv[2], input = argv[3];
  std::string out_path, edges_path, truth_path, preset;
  std::vector<std::string> args;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] {
      if (i + 1 >= argc) throw InvalidOption(a + " needs a value");
      return std::string(argv[++i]);
    };
    if (a == "--out") out_path = next();
    else if (a == "--edges") edges_path = next();
    else if (a == "--truth") truth_path = next();
    else if (a == "--preset") preset = next();
    else args.push_back(a);
  }
  const Mesh in = read_mesh(input);
  const Outcome r = run_method(method, in, args, preset);
  if (!out_path.empty()) write_mesh(r.mesh, out_path);
  if (!edges_path.empty()) write_edge_values(r.mesh, r.labels, "label", edges_path);
  std::string line = fmt::format("{} {} cpu {:.3f} wall {:.3f}", method, input, r.cpu, r.wall);
  if (!truth_path.empty()) {
    const Mesh truth = read_mesh(truth_path);
    const Comparison c = compare_meshes(r.mesh, truth);
    line += fmt::format(" err {:.3f} ev {:.4e}", c.mean_normal_error_deg, c.ev_relative);
    if (r.labels.size() > 0 && c.faces_by_index) {
      const LabelScore s = label_score(r.mesh, r.labels, truth);
      if (s.truth > 0) line += fmt::format(" P {:.2f} R {:.2f}", s.precision, s.recall);
    }
  }
  fmt::print("{}\n  {}\n", line, r.params);
  return 0;
}

// A closed double cone ("spindle"): a rim of n vertices on the unit circle and two apexes of valence n.
Mesh spindle(int n, double height) {
  MatrixX3d V(n + 2, 3);
  MatrixX3i F(2 * n, 3);
  for (int i = 0; i < n; ++i) V.row(i) << std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0.0;
  V.row(n) << 0, 0, height;
  V.row(n + 1) << 0, 0, -height;
  for (int i = 0; i < n; ++i) {
    F.row(i) << i, (i + 1) % n, n;
    F.row(n + i) << (i + 1) % n, i, n + 1;
  }
  return make_mesh(V, F);
}

// The valence test: every method on a noisy spindle whose two apexes have valence n.
int cmd_fan(int argc, char** argv) {
  const int n = argc >= 3 ? std::atoi(argv[2]) : 8000;
  const Mesh clean = spindle(n, 0.5);
  Mesh noisy = clean;
  NoiseOptions no;
  no.sigma = 0.1;
  set_positions(noisy, add_noise(clean, no));
  std::vector<std::string> methods = {"mrf", "mrf-normal", "surfel"};
  for (int i = 3; i < argc; ++i) methods.assign(argv + 3, argv + argc);
  for (const std::string& spec : methods) {
    // METHOD or METHOD:name=value,name=value
    const std::string m = spec.substr(0, spec.find(':'));
    std::vector<std::string> args;
    if (spec.find(':') != std::string::npos) {
      std::string rest = spec.substr(spec.find(':') + 1);
      for (size_t at = 0; at <= rest.size();) {
        const size_t comma = std::min(rest.find(',', at), rest.size());
        args.push_back(rest.substr(at, comma - at));
        at = comma + 1;
      }
    }
    const Outcome r = run_method(m, noisy, args, "");
    fmt::print("fan valence {} {}: cpu {:.3f} s, wall {:.3f} s, normal error {:.2f} deg\n", n, spec, r.cpu, r.wall,
               compare_meshes(r.mesh, clean).mean_normal_error_deg);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && std::strcmp(argv[1], "run") == 0) return cmd_run(argc, argv);
    if (argc >= 2 && std::strcmp(argv[1], "fan") == 0) return cmd_fan(argc, argv);
    fmt::print(stderr, "usage: denoise_bench run METHOD IN [--out OUT] [--edges E] [--truth T] [--preset P] [k=v ...]\n");
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "denoise_bench: {}\n", e.what());
    return 1;
  }
}
