#include "cli.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/results.h"

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
  nlohmann::json j = {{"mesh", f.mesh}, {"caption", f.caption}, {"view", f.view}, {"up", f.up}};
  if (!f.compare.empty()) j["compare"] = f.compare;
  if (!f.field.empty()) j["field"] = f.field;
  if (!f.truth.empty()) j["truth"] = f.truth;
  if (!f.edges.empty()) j["edges"] = f.edges;
  if (f.checker) j["checker"] = true;
  if (!f.sets_range) j["sets_range"] = false;
  (*ctx.report)["figures"].push_back(std::move(j));
}

MeshIo::MeshIo(CLI::App& app, const std::string& output_help) {
  app.add_option("IN", input, "input mesh (- reads standard input)")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", output, output_help + " (- writes standard output, in the format of --format)")
      ->required()->check(MeshOutputFile);
  app.add_flag("--ascii", ascii, "ascii PLY/STL output");
}

std::string printable(std::string_view text, size_t max_chars) {
  std::string out;
  out.reserve(std::min(text.size(), max_chars));
  for (const char ch : text) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) out += fmt::format("\\x{:02x}", c);
    else out += ch;
  }
  return out;
}

void info(const std::string& line) {
  // A line is one line: an output named with ESC or a newline in it is shown escaped (issue 30).
  if (!globals().quiet) std::fprintf(stderr, "%s\n", printable(line).c_str());
}

void write_report(const std::string& path, nlohmann::json result, double seconds, nlohmann::json parameters) {
  result.update(run_time_results().report({seconds}));
  result["parameters"] = std::move(parameters);
  write_text_atomic(path, result.dump(2) + "\n");
  info("wrote " + path);
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
  const bool to_stdout = path == kStdioPath;
  if (to_stdout) opt.format = format_from_name(globals().stdout_format);
  write_mesh(mesh, path, opt);
  const std::string where = to_stdout ? fmt::format("standard output ({})", globals().stdout_format) : path;
  info(fmt::format("wrote {} ({} vertices, {} faces)", where, mesh.n_vertices(), mesh.n_faces()));
}

Outputs::Outputs(std::initializer_list<std::string> inputs,
                 std::initializer_list<std::pair<std::string, std::string>> outputs) {
  for (const auto& i : inputs) input(i);
  for (const auto& [path, what] : outputs) output(path, what);
}

void Outputs::input(const std::string& path) {
  if (!path.empty() && path != kStdioPath) tx_.declare_input(path);
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
      if (path == kStdioPath) return {};  // standard input
      require_input_file(path);  // names a loop of links, a directory, a FIFO or a device as such
      format_from_path(path);    // an unknown extension: IoError naming the formats
      return {};
    },
    "MESH", "ExistingMeshFile");

const CLI::Validator ExistingFile(
    [](std::string& path) -> std::string {
      require_input_file(path);
      return {};
    },
    "FILE", "ExistingFile");

// Outputs are checked by their flags, while parsing: a name no writer takes fails before the input is read.
const CLI::Validator MeshOutputFile(
    [](std::string& path) -> std::string {
      if (path == kStdioPath) return {};  // standard output, in the format of --format
      output_format_from_path(path);      // an unknown extension (or .gz): IoError naming the formats
      return {};
    },
    "MESH", "MeshOutputFile");

CLI::Validator OutputWithExtension(const std::string& extension, const std::string& explanation) {
  std::string desc = extension.substr(1);
  std::transform(desc.begin(), desc.end(), desc.begin(), [](unsigned char c) { return std::toupper(c); });
  return CLI::Validator(
      [extension, explanation](std::string& path) -> std::string {
        std::string ext = std::filesystem::path(path).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
        if (ext != extension) throw IoError(fmt::format("{}: {}", path, explanation));
        return {};
      },
      desc, "OutputWithExtension");
}

const CLI::Validator TextureOutputFile = OutputWithExtension(
    ".ply", "a texture file is a PLY (base mesh, vertex height and lean, edge tilt): name it .ply");

const CLI::Validator FiniteNumber(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(v)) return fmt::format("'{}' is not a finite number", text);
      return {};
    },
    "", "FiniteNumber");

}  // namespace geotex::cli

namespace geotex::cli {

namespace {
// Optimal string alignment distance: Levenshtein with adjacent transpositions ("sigam" is 1 from "sigma").
size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string_view without_dashes(std::string_view s) {
  while (!s.empty() && s.front() == '-') s.remove_prefix(1);
  return s;
}

// "-x", "--name", "--name=value"; not "-0.5" (a negative number) or "-" (stdin).
bool looks_like_flag(const std::string& arg) {
  return arg.size() > 1 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1])) && arg[1] != '.';
}

// Every spelling of every option of \p app and of the commands above it (global flags go anywhere).
std::vector<std::string> flag_names(const CLI::App* app) {
  std::vector<std::string> names;
  for (; app; app = app->get_parent())
    for (const CLI::Option* o : app->get_options()) {
      for (const auto& l : o->get_lnames()) names.push_back("--" + l);
      for (const auto& s : o->get_snames()) names.push_back("-" + s);
    }
  return names;
}

// "geotex texture": the command line up to \p app.
std::string command_path(const CLI::App* app) {
  std::string path;
  for (; app; app = app->get_parent()) path = app->get_name() + (path.empty() ? "" : " " + path);
  return path;
}
}  // namespace

std::string closest_name(std::string_view name, const std::vector<std::string>& candidates) {
  // A slip, not another word: at most a third of the letters differ (one for short names, three at most).
  const std::string_view bare = without_dashes(name);
  const size_t limit = std::clamp<size_t>(bare.size() / 3, 1, 3);
  std::string best;
  size_t best_distance = limit + 1;
  for (const auto& c : candidates) {
    const size_t d = edit_distance(bare, without_dashes(c));
    if (d < best_distance) best = c, best_distance = d;
  }
  return best;
}

std::optional<std::string> unknown_argument_message(const CLI::App& app) {
  const std::vector<std::string> left = app.remaining(true);
  if (left.empty()) return std::nullopt;
  const CLI::App* at = &app;  // the last command given
  while (!at->get_subcommands().empty()) at = at->get_subcommands().front();
  // Visible subcommands: a command that needs one and got none reads its first word as the typo.
  std::vector<std::string> commands;
  for (const CLI::App* s : at->get_subcommands([](const CLI::App* s) { return !s->get_group().empty(); }))
    commands.push_back(s->get_name());
  const std::string where = command_path(at);
  if (!commands.empty()) {
    for (const auto& arg : left) {
      if (looks_like_flag(arg)) continue;
      const std::string what = at->get_parent() ? "unknown " + at->get_name() + " command " : "unknown command ";
      const std::string best = closest_name(arg, commands);
      return what + arg + (best.empty() ? " (see " + where + " --help)" : " (did you mean " + best + "?)");
    }
  }
  for (const auto& arg : left) {
    if (!looks_like_flag(arg)) continue;
    const std::string flag = arg.substr(0, arg.find('='));
    const std::string best = closest_name(flag, flag_names(at));
    return "unknown flag " + flag + (best.empty() ? " (see " + where + " --help)" : " (did you mean " + best + "?)");
  }
  return std::nullopt;
}

}  // namespace geotex::cli
