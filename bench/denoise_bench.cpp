// Denoising experiments and measurements (bench/denoise.md): runs the library's denoisers with options
// given by name (from their option tables, as the CLI and Python will), scores them against a truth,
// and measures CPU time of the library call alone.
//
//   denoise_bench run METHOD IN [--out OUT] [--edges E.ply] [--truth T] [--preset P] [name=value ...]
//       METHOD: mrf | mrf-normal | surfel
//   denoise_bench fan VALENCE                 the valence test: one vertex of the given valence
//
// Output: one line "key value ..." per run (normal error, Ev, label precision/recall, CPU seconds).

#include <algorithm>
#include <chrono>
#include <sys/resource.h>
#include <cstdio>
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
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/surfel.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }
// CPU seconds (user + system) of the finished child processes.
double child_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
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
  } else if (method == "auto") {
    const auto o = parse_options<AutoDenoiseOptions>(args, preset);
    const AutoDenoiseResult r = auto_denoise(in, o);
    out.params = describe(r.resolved);
    for (const auto& c : r.choices) out.params += "\n  " + c;
    for (const auto& [name, sec] : r.seconds) out.params += fmt::format("\n  {}: {:.3f} s", name, sec);
    out.mesh = in;
    set_positions(out.mesh, r.positions);
    out.labels = r.edge_labels;
  } else if (method.rfind("peer-", 0) == 0) {
    // A published denoiser (../shared/peers, gd_denoise METHOD IN OUT), run as a process on OBJ files.
    const char* gd = std::getenv("GEOTEX_PEERS");
    if (!gd) throw InvalidOption("set GEOTEX_PEERS to the gd_denoise binary");
    const std::string dir = "/tmp/denoise_bench_peer", in_path = dir + "/in.obj", out_path = dir + "/out.obj";
    std::filesystem::create_directories(dir);
    WriteOptions wo;
    write_mesh(in, in_path, wo);
    const double c0 = child_cpu_seconds();
    const std::string cmd = fmt::format("{} {} {} {} > /dev/null 2>&1", gd, method.substr(5), in_path, out_path);
    if (std::system(cmd.c_str()) != 0) throw InvalidOption("peer failed: " + cmd);
    out.mesh = read_mesh(out_path);
    out.cpu = child_cpu_seconds() - c0;
    out.wall = wall_seconds() - w0;
    return out;
  } else if (method == "none") {
    out.mesh = in;
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

// denoise_bench score RESULT TRUTH [LABELS.ply]: "error Ev precision recall" (labels against the truth's
// edges above 30°, matched by their vertices; "- -" without labels).
int cmd_score(int argc, char** argv) {
  if (argc < 4) throw InvalidOption("usage: denoise_bench score RESULT TRUTH [LABELS.ply]");
  const Mesh result = read_mesh(argv[2]), truth = read_mesh(argv[3]);
  const Comparison c = compare_meshes(result, truth);
  std::string labels = "-\t-";
  if (argc >= 5) {
    const EdgeValues ev = read_edge_values(argv[4], "label");
    std::vector<int> keep;
    for (Eigen::Index i = 0; i < ev.values.size(); ++i)
      if (ev.values[i] > 0.5) keep.push_back(static_cast<int>(i));
    MatrixX2i L(keep.size(), 2);
    for (size_t k = 0; k < keep.size(); ++k) L.row(k) = ev.edges.row(keep[k]);
    const Eigen::VectorXd D = dihedral_angles(truth);
    const MatrixX2i E = edges(truth);
    std::vector<int> sharp;
    for (Eigen::Index i = 0; i < D.size(); ++i)
      if (std::abs(D[i]) > 30.0 * M_PI / 180.0) sharp.push_back(static_cast<int>(i));
    MatrixX2i T(sharp.size(), 2);
    for (size_t k = 0; k < sharp.size(); ++k) T.row(k) = E.row(sharp[k]);
    const LabelScore s = score_edge_labels(L, T);
    labels = fmt::format("{:.2f}\t{:.2f}", s.precision, s.recall);
  }
  fmt::print("{:.3f}\t{:.3e}\t{}\n", c.mean_normal_error_deg, c.ev_relative, labels);
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Synthetic sets: clean models with geotex noise (never the shared noisy pairs).

struct NoiseCase {
  std::string name;  // g0.3 (Gaussian, random directions), n0.3 (along normals), i0.5 (impulsive, 10 % of vertices)
  NoiseOptions options;
};

NoiseCase parse_noise(const std::string& spec) {
  NoiseCase c;
  c.name = spec;
  c.options.sigma = std::atof(spec.c_str() + 1);
  if (spec[0] == 'n') c.options.along_normal = true;
  else if (spec[0] == 'i') c.options.impulsive_fraction = 0.1;
  else if (spec[0] == 'j') c.options.impulsive_fraction = 0.5;
  else if (spec[0] != 'g' && spec[0] != 'j') throw InvalidOption("noise '" + spec + "': g|n|i followed by sigma");
  return c;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  for (size_t at = 0; at <= s.size();) {
    const size_t next = std::min(s.find(sep, at), s.size());
    if (next > at) out.push_back(s.substr(at, next - at));
    at = next + 1;
  }
  return out;
}

// METHOD or METHOD:name=value,name=value (or METHOD@preset:…).
struct MethodSpec {
  std::string text, method, preset;
  std::vector<std::string> args;
};
MethodSpec parse_method(const std::string& spec) {
  MethodSpec m;
  m.text = spec;
  const size_t colon = spec.find(':');
  m.method = spec.substr(0, colon);
  if (colon != std::string::npos) m.args = split(spec.substr(colon + 1), ',');
  if (const size_t at = m.method.find('@'); at != std::string::npos) {
    m.preset = m.method.substr(at + 1);
    m.method = m.method.substr(0, at);
  }
  return m;
}

Mesh load_model(const std::string& name) {
  const std::filesystem::path dir(GEOTEX_DATA_DIR);
  if (name == "sharp-sphere") {
    // A sphere cut flat at |z| = 0.6: circular creases of about 53° between the caps and the sphere.
    Mesh m = icosphere(5, 1.0);
    MatrixX3d V = positions(m);
    for (Eigen::Index i = 0; i < V.rows(); ++i) V(i, 2) = std::clamp(V(i, 2), -0.6, 0.6);
    set_positions(m, V);
    return m;
  }
  if (name.find('/') != std::string::npos) return read_mesh(name);
  if (name == "cube") return subdivided_cube(40);
  if (name == "sphere") return icosphere(5, 1.0);
  if (name == "cylinder") return cylinder(0.5, 1.0, 96, 48);
  if (name == "torus") return torus(1.0, 0.35, 160, 60);
  for (const char* ext : {".obj", ".ply"})
    if (std::filesystem::exists(dir / (name + ext))) return read_mesh(dir / (name + ext));
  throw InvalidOption("unknown model '" + name + "'");
}

int cmd_synth(int argc, char** argv) {
  std::vector<std::string> models = {"fandisk", "cow", "spot", "woody", "cheburashka", "stanford-bunny"};
  std::vector<std::string> noises = {"g0.1", "g0.3", "g0.5", "g0.7", "n0.3", "i0.5"};
  std::vector<MethodSpec> methods;
  std::string tsv;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--models" && i + 1 < argc) models = split(argv[++i], ',');
    else if (a == "--noise" && i + 1 < argc) noises = split(argv[++i], ',');
    else if (a == "--tsv" && i + 1 < argc) tsv = argv[++i];
    else methods.push_back(parse_method(a));
  }
  std::FILE* out = tsv.empty() ? nullptr : std::fopen(tsv.c_str(), "a");
  struct Sum { double err = 0, ev = 0, cpu = 0, p = 0, r = 0; int n = 0, nl = 0; long flipped = 0; };
  std::vector<Sum> sums(methods.size());
  for (const std::string& model : models) {
    const Mesh clean = load_model(model);
    const MatrixX3d FN = face_normals(clean);
    for (const std::string& nspec : noises) {
      const NoiseCase nc = parse_noise(nspec);
      Mesh noisy = clean;
      set_positions(noisy, add_noise(clean, nc.options));
      for (size_t k = 0; k < methods.size(); ++k) {
        const Outcome r = run_method(methods[k].method, noisy, methods[k].args, methods[k].preset);
        const Comparison c = compare_meshes(r.mesh, clean);
        long flipped = 0;
        std::string labels = "- -";
        if (c.faces_by_index) {
          const MatrixX3d RN = face_normals(r.mesh);
          for (Eigen::Index f = 0; f < FN.rows(); ++f) flipped += RN.row(f).dot(FN.row(f)) < 0;
          if (r.labels.size() > 0) {
            const LabelScore ls = label_score(r.mesh, r.labels, clean);
            if (ls.truth > 0.01 * clean.n_edges()) {
              labels = fmt::format("{:.2f} {:.2f}", ls.precision, ls.recall);
              sums[k].p += ls.precision;
              sums[k].r += ls.recall;
              ++sums[k].nl;
            }
          }
        }
        sums[k].err += c.mean_normal_error_deg;
        sums[k].ev += c.ev_relative;
        sums[k].cpu += r.cpu;
        sums[k].flipped += flipped;
        ++sums[k].n;
        const std::string line = fmt::format("{}\t{}\t{}\t{:.3f}\t{:.4e}\t{}\t{}\t{:.3f}", methods[k].text, model, nspec,
                                             c.mean_normal_error_deg, c.ev_relative, labels, flipped, r.cpu);
        fmt::print("{}\n", line);
        if (out) fmt::print(out, "{}\n", line);
        std::fflush(stdout);
      }
    }
  }
  if (out) std::fclose(out);
  fmt::print("\n| method | mean normal error | mean Ev | P / R (creased) | flipped faces | CPU s |\n|---|---|---|---|---|---|\n");
  for (size_t k = 0; k < methods.size(); ++k) {
    const Sum& s = sums[k];
    fmt::print("| {} | {:.3f} | {:.3e} | {} | {} | {:.2f} |\n", methods[k].text, s.err / s.n, s.ev / s.n,
               s.nl ? fmt::format("{:.2f} / {:.2f}", s.p / s.nl, s.r / s.nl) : std::string("-"), s.flipped, s.cpu);
  }
  return 0;
}

// The noise estimate against the sigma used, over models and noise cases.
int cmd_noise(int argc, char** argv) {
  std::vector<std::string> models = {"fandisk", "cow", "spot", "woody", "cheburashka", "stanford-bunny", "igea"};
  std::vector<std::string> noises = {"g0.05", "g0.1", "g0.2", "g0.3", "g0.5", "g0.7", "n0.1", "n0.3", "n0.7"};
  if (argc >= 3) models = split(argv[2], ',');
  if (argc >= 4) noises = split(argv[3], ',');
  for (const std::string& model : models) {
    const Mesh clean = load_model(model);
    const NoiseEstimate e0 = estimate_noise(clean);
    std::string line = fmt::format("{:16s} clean {:.3f}", model, e0.sigma);
    for (const std::string& nspec : noises) {
      const NoiseCase nc = parse_noise(nspec);
      Mesh noisy = clean;
      set_positions(noisy, add_noise(clean, nc.options));
      const double c0 = cpu_seconds();
      const NoiseEstimate e = estimate_noise(noisy);
      const double est = nc.options.along_normal ? e.normal_sigma : e.sigma;
      line += fmt::format("  {} {:.3f} ({:+.0f}%, {:.2f}s)", nspec, est, 100 * (est / nc.options.sigma - 1), cpu_seconds() - c0);
    }
    fmt::print("{}\n", line);
  }
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
    if (argc >= 2 && std::strcmp(argv[1], "synth") == 0) return cmd_synth(argc, argv);
    if (argc >= 2 && std::strcmp(argv[1], "noise") == 0) return cmd_noise(argc, argv);
    if (argc >= 2 && std::strcmp(argv[1], "score") == 0) return cmd_score(argc, argv);
    fmt::print(stderr, "usage: denoise_bench run METHOD IN [--out OUT] [--edges E] [--truth T] [--preset P] [k=v ...]\n");
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "denoise_bench: {}\n", e.what());
    return 1;
  }
}
