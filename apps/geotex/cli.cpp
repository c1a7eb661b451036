#include "cli.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#include <fmt/format.h>

#include "geotex/core/error.h"

namespace geotex::cli {

GlobalOptions& globals() {
  static GlobalOptions g;
  return g;
}
std::vector<Command>& commands() {
  static std::vector<Command> c;
  return c;
}
std::vector<DemoStep>& demo_steps() {
  static std::vector<DemoStep> s;
  return s;
}

std::string demo_section(int order) {
  // The pipeline: what goes in, the toolkit under everything, then denoising, texture, resizing.
  static const std::pair<int, const char*> sections[] = {
      {0, "Input"}, {20, "Toolkit"}, {40, "Denoising"}, {80, "Texture"}, {85, "Resizing"}, {900, "Report"}};
  const char* name = sections[0].second;
  for (const auto& [from, s] : sections)
    if (order >= from) name = s;
  return name;
}

void add_figure(const DemoContext& ctx, const DemoFigure& f) {
  nlohmann::json j = {{"mesh", f.mesh}, {"caption", f.caption}, {"view", f.view}};
  if (!f.compare.empty()) j["compare"] = f.compare;
  if (!f.field.empty()) j["field"] = f.field;
  if (!f.truth.empty()) j["truth"] = f.truth;
  if (!f.edges.empty()) j["edges"] = f.edges;
  if (f.checker) j["checker"] = true;
  if (!f.sets_range) j["sets_range"] = false;
  (*ctx.report)["figures"].push_back(std::move(j));
}

MeshIo::MeshIo(CLI::App& app, const std::string& output_help) {
  app.add_option("IN", input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", output, output_help)->required();
  app.add_flag("--ascii", ascii, "ascii PLY/STL output");
}

void info(const std::string& line) {
  if (!globals().quiet) std::fprintf(stderr, "%s\n", line.c_str());
}

Mesh load_mesh(const std::string& path, ReadReport* report, bool strict) {
  ReadReport rep;
  ReadOptions opt;
  opt.strict = strict;
  Mesh mesh = read_mesh(path, opt, &rep);
  for (const auto& w : rep.warnings) info(fmt::format("geotex: warning: {}: {}", path, w));
  for (const auto& n : rep.notes) info(fmt::format("geotex: note: {}: {}", path, n));
  if (report) *report = rep;
  return mesh;
}

void save_mesh(const Mesh& mesh, const std::string& path, bool binary) {
  WriteOptions opt;
  opt.binary = binary;
  write_mesh(mesh, path, opt);
  info(fmt::format("wrote {} ({} vertices, {} faces)", path, mesh.n_vertices(), mesh.n_faces()));
}

Outputs::Outputs(std::initializer_list<std::string> inputs,
                 std::initializer_list<std::pair<std::string, std::string>> outputs) {
  for (const auto& i : inputs) input(i);
  for (const auto& [path, what] : outputs) output(path, what);
}

void Outputs::input(const std::string& path) {
  if (!path.empty()) tx_.declare_input(path);
}

void Outputs::output(const std::string& path, const std::string& what) {
  if (!path.empty()) tx_.declare(path, what);
}

ProgressFn progress_printer(const std::string& label) {
  if (globals().quiet) return {};
  if (::isatty(STDERR_FILENO)) {  // one line redrawn in place
    return [label](double fraction, std::string_view stage) {
      const int pct = static_cast<int>(fraction * 100 + 0.5);
      std::fprintf(stderr, "\r%s: %.*s %3d%%%s", label.c_str(), int(stage.size()), stage.data(), pct,
                   pct >= 100 ? "\n" : "");
    };
  }
  // A log or a pipe: every line stays, so a run that ends within the first interval prints none, and
  // a longer one a line per interval at most (the stage as it is then), and its 100% once after them.
  using Clock = std::chrono::steady_clock;
  struct State {
    Clock::time_point start = Clock::now(), last = start;
    bool pending_end = false;  // a line was printed since the last 100%
  };
  auto s = std::make_shared<State>();
  return [label, s](double fraction, std::string_view stage) {
    const int pct = static_cast<int>(fraction * 100 + 0.5);
    const Clock::time_point now = Clock::now();
    const bool end = pct >= 100;
    if (end ? !s->pending_end : now - s->last < kLogProgressInterval) return;
    s->last = now;
    s->pending_end = !end;
    const double seconds = std::chrono::duration<double>(now - s->start).count();
    std::fprintf(stderr, "%s: %.*s %d%% (%.0f s)\n", label.c_str(), int(stage.size()), stage.data(), pct, seconds);
  };
}

// A missing or unreadable input is a file error (exit 1, as the README says), not a flag error (exit 2):
// these validators throw IoError, which CLI11 lets through its parser (it catches ValidationError only).
const CLI::Validator ExistingMeshFile(
    [](std::string& path) -> std::string {
      std::error_code ec;
      if (!std::filesystem::exists(path, ec)) throw IoError(fmt::format("{}: no such file", path));
      if (std::filesystem::is_directory(path, ec)) throw IoError(fmt::format("{}: is a directory", path));
      format_from_path(path);  // an unknown extension: IoError naming the formats
      return {};
    },
    "MESH", "ExistingMeshFile");

const CLI::Validator ExistingFile(
    [](std::string& path) -> std::string {
      std::error_code ec;
      if (!std::filesystem::exists(path, ec)) throw IoError(fmt::format("{}: no such file", path));
      if (std::filesystem::is_directory(path, ec)) throw IoError(fmt::format("{}: is a directory", path));
      return {};
    },
    "FILE", "ExistingFile");

const CLI::Validator FiniteNumber(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(v)) return fmt::format("'{}' is not a finite number", text);
      return {};
    },
    "", "FiniteNumber");

}  // namespace geotex::cli
