// geotex denoise IN -o OUT --method NAME: dispatch to a registered denoising method; write the mesh,
// the edge labels (PLY edge element and OBJ polylines) and a JSON report.

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/denoise/results.h"

namespace geotex::cli {

std::vector<DenoiseMethod>& denoise_methods() {
  static std::vector<DenoiseMethod> m;
  return m;
}

namespace cmd_denoise {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string method = "auto", edges_ply, edges_obj, report;
  double label_threshold = 0.5;
};

const DenoiseMethod& find_method(const std::string& name) {
  for (const auto& m : denoise_methods())
    if (m.name == name) return m;
  throw InvalidOption(fmt::format("unknown denoising method '{}'", name));
}

Registrar reg{50, "denoise", "Denoise a mesh and find its sharp edges (methods: see --method)", [](CLI::App& app) {
  auto io = std::make_shared<MeshIo>(app);
  auto a = std::make_shared<Args>();
  auto flags = std::make_shared<FlagSet>(app);
  std::vector<std::string> names;
  std::string help = "denoising method:";
  for (const auto& m : denoise_methods()) {
    names.push_back(m.name);
    help += "\n  " + m.name + ": " + m.help;
  }
  app.add_option("--method", a->method, help)->check(CLI::IsMember(names))->capture_default_str();
  // Each file has one format: an --edges name not ending in .ply is refused, not written as PLY under
  // another name nor quietly turned into OBJ lines (which would drop the labels of the smooth edges).
  app.add_option("--edges", a->edges_ply,
                 "write every edge's label as PLY (edge element: vertex1 vertex2 label); the name must end in .ply "
                 "(OBJ line segments of the sharp edges: --edges-obj)")
      ->check(OutputWithExtension(".ply", "--edges writes PLY (every edge with its label): name it .ply, or use "
                                          "--edges-obj for the sharp edges as OBJ line segments"));
  app.add_option("--edges-obj", a->edges_obj,
                 "write the sharp edges (label above --label-threshold) as OBJ line segments; the name must end in .obj")
      ->check(OutputWithExtension(".obj", "--edges-obj writes OBJ line segments: name it .obj, or use --edges for "
                                          "every edge's label as PLY"));
  app.add_option("--label-threshold", a->label_threshold, "label above which an edge counts as sharp (OBJ output)")
      ->check(FiniteNumber)->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--report", a->report, "write a JSON report (energies per iteration, parameters, time)");
  for (const auto& m : denoise_methods()) m.add_flags(*flags);
  app.callback([io, a, flags] {
    const DenoiseMethod& method = find_method(a->method);
    const DenoiseRun run = method.prepare(*flags);  // options resolved (and refused) before any work
    Outputs out({io->input}, {{io->output, "-o"}, {a->edges_ply, "--edges"}, {a->edges_obj, "--edges-obj"},
                              {a->report, "--report"}});
    if (method.outputs)
      for (const auto& [path, flag] : method.outputs()) out.output(path, flag);
    const Mesh input = load_mesh(io->input);
    const auto t0 = std::chrono::steady_clock::now();
    DenoiseOutput r = run(input, progress_printer("denoise " + a->method));
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    info(fmt::format("denoised with {} in {:.2f} s", a->method, sec));
    const bool have_labels = r.edge_labels.size() > 0;
    if ((!a->edges_ply.empty() || !a->edges_obj.empty()) && !have_labels)
      throw InvalidInput(fmt::format("method '{}' does not label edges", a->method));
    save_mesh(r.mesh, io->output, !io->ascii);
    if (!a->edges_ply.empty()) {
      write_edge_values(r.mesh, r.edge_labels, "label", a->edges_ply, !io->ascii);
      info(fmt::format("wrote {} (edge labels)", a->edges_ply));
    }
    if (!a->edges_obj.empty()) {
      const MatrixX2i E = edges(r.mesh);
      std::vector<int> rows;
      for (Eigen::Index i = 0; i < E.rows(); ++i)
        if (r.edge_labels[i] > a->label_threshold) rows.push_back(static_cast<int>(i));
      MatrixX2i S(rows.size(), 2);
      for (size_t k = 0; k < rows.size(); ++k) S.row(k) = E.row(rows[k]);
      write_polylines_obj(positions(r.mesh), S, a->edges_obj);
      info(fmt::format("wrote {} ({} sharp edges)", a->edges_obj, rows.size()));
    }
    if (!a->report.empty()) {
      nlohmann::json parameters = std::move(r.report["parameters"]);  // the method's options, as it ran
      r.report.erase("parameters");
      r.report.update(denoise_run_results().report(geotex::DenoiseRun{a->method, sec}));
      r.report["input"] = io->input;  // the CLI's own: the input file
      write_report(a->report, std::move(r.report), sec, std::move(parameters));
    }
    out.commit();
  });
}};

}  // namespace cmd_denoise
}  // namespace geotex::cli
