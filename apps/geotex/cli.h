#pragma once
// Shared pieces of the geotex command-line tool: subcommand and demo-step registries, reading and
// writing with user-facing messages, progress lines.

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/core/output.h"
#include "geotex/core/progress.h"

namespace geotex::cli {

struct GlobalOptions {
  bool quiet = false;  // no progress or warnings on stderr
  std::string stdout_format = "ply";  // --format: the format of a mesh written to standard output (-o -)
};
GlobalOptions& globals();

// A subcommand registers itself from its own file: `static Registrar r{order, "name", "help", setup};`.
struct Command {
  int order;
  std::string name, help;
  std::function<void(CLI::App&)> setup;  // adds options and a callback to the subcommand
};
std::vector<Command>& commands();
struct Registrar {
  Registrar(int order, std::string name, std::string help, std::function<void(CLI::App&)> setup) {
    commands().push_back({order, std::move(name), std::move(help), std::move(setup)});
  }
};

// Steps of `geotex demo`, registered by each capability's demo file the same way.
struct DemoContext {
  std::filesystem::path dir;  // output folder
  nlohmann::json* report;     // each step adds its own section
  const nlohmann::json* steps = nullptr;  // the sections of the steps run before (the report reads them)
  bool quick = false;         // --quick: coarse shapes and no real model (tests)
  std::filesystem::path data; // the shared data folder ("" or absent: generated shapes only)
  std::filesystem::path shipped;  // the project's own small real models (data/: spot, CC0); "" with --quick
};

// A real model by file name: from the shared data when it is there, else from the shipped models;
// empty when neither has it (and always with --quick).
std::filesystem::path demo_model(const DemoContext& ctx, const std::string& name);
// The shipped models' folder: installed beside the executable (share/geotex/data; data/ in the
// Python package), else the source tree's data/.
std::filesystem::path shipped_data_dir();

// The part of the report page a step belongs to, from its order: the pipeline's order (input,
// toolkit, denoising, texture, resizing; then the report itself).
std::string demo_section(int order);

// A picture on the demo's index.html, added by a step with add_figure() and drawn by the report step
// (demo/report.cpp) in the steps' order.
struct DemoFigure {
  std::string mesh;      // mesh file in the demo folder
  std::string caption;   // what it shows, with the measured numbers
  std::string compare;   // figures with the same key share their camera and their colour range
  std::string field;     // vertex property shown in colour ("error": distance to `truth`; "": none)
  std::string truth;     // the clean mesh file for "error"
  std::string edges;     // a PLY file with an edge "label" property, drawn as red lines
  bool checker = false;  // draw the mesh's "param_u", "param_v" vertex properties as a checkerboard
  bool sets_range = true;  // false: its colours may saturate (a noisy input beside its results)
  std::string view = "iso";  // iso, front, top
  std::string up = "z";      // the model's up axis: generated shapes are z-up; real models "auto"
};
void add_figure(const DemoContext& ctx, const DemoFigure& figure);
struct DemoStep {
  int order;
  std::string name;
  std::function<void(const DemoContext&)> run;
};
std::vector<DemoStep>& demo_steps();
struct DemoRegistrar {
  DemoRegistrar(int order, std::string name, std::function<void(const DemoContext&)> run) {
    demo_steps().push_back({order, std::move(name), std::move(run)});
  }
};

// IN, -o/--output OUT and --ascii: the arguments of every mesh-to-mesh command.
struct MeshIo {
  std::string input, output;
  bool ascii = false;
  explicit MeshIo(CLI::App& app, const std::string& output_help = "output mesh");
};

// Read a mesh, printing the reader's warnings (what was dropped, strips decoded, …) unless quiet.
// "-" is standard input.
Mesh load_mesh(const std::string& path, ReadReport* report = nullptr, bool strict = false);
// Write a mesh (atomically) and say where it went unless quiet (on stderr). "-" is standard output,
// in the format of --format.
void save_mesh(const Mesh& mesh, const std::string& path, bool binary = true);

// The files of one run (geotex/core/output.h): inputs and outputs are declared, and every output is
// checked, before any work; outputs go to temporaries and are put in place together by commit().
// An output that names an input, a special file, a read-only file or an unwritable folder fails here.
class Outputs {
 public:
  Outputs(std::initializer_list<std::string> inputs, std::initializer_list<std::pair<std::string, std::string>> outputs);
  void input(const std::string& path);                          // "" is skipped
  void output(const std::string& path, const std::string& what);  // "" is skipped
  void commit() { tx_.commit(); }

 private:
  OutputTransaction tx_;
};

// A progress callback printing "stage 42%" on stderr: on a terminal one line redrawn in place; otherwise
// (a log, a pipe) nothing during the first kLogProgressInterval, then a line per interval at most, and
// the final 100% only if a line was printed.
ProgressFn progress_printer(const std::string& label);
inline constexpr std::chrono::seconds kLogProgressInterval{5};
//! \p text with control bytes shown as \xNN (a name or a file's bytes cannot disturb the terminal or forge a
//! line), cut after about \p max_chars with "..." appended.
std::string printable(std::string_view text, size_t max_chars = std::string::npos);
//! Write a --report: \p result (a result table's report(), core/results.h) with the run's "seconds" and
//! "parameters" (options_json() of the options used), as JSON; says "wrote PATH".
void write_report(const std::string& path, nlohmann::json result, double seconds, nlohmann::json parameters);
void info(const std::string& line);  // stderr unless quiet; the line printable()

//! The candidate closest to \p name by edit distance (dashes aside), or "" when none is within a slip
//! of it (a third of its letters, at least one and at most three).
std::string closest_name(std::string_view name, const std::vector<std::string>& candidates);
//! After a failed parse: "unknown flag --sigmaa (did you mean --sigma?)" for the first argument the
//! command line did not take (a mistyped command, or else a flag), or nullopt when every argument was
//! taken. It is the error to report even when a validator failed first: an unknown flag shifts the
//! arguments after it (its value becomes IN, which then "does not exist").
std::optional<std::string> unknown_argument_message(const CLI::App& app);

// Validators for CLI11.
//! An input mesh: "-" (standard input), or an existing regular file with a mesh extension; IoError
//! (exit 1) naming what it is otherwise (missing, a loop of links, a directory, a FIFO, a device).
extern const CLI::Validator ExistingMeshFile;
//! An existing file that is not a folder (texture, deform handles, point files); IoError (exit 1) otherwise.
extern const CLI::Validator ExistingFile;
extern const CLI::Validator FiniteNumber;  // refuses nan and inf (hand-written numeric flags)
//! An output mesh name with a format geotex writes (.obj, .ply, .off, .stl, .gltf, .glb, or "-" for
//! standard output); IoError (exit 1) otherwise, while parsing, so before any work.
extern const CLI::Validator MeshOutputFile;
//! An output name ending in \p extension (".ply"); IoError "PATH: explanation" otherwise, while parsing.
CLI::Validator OutputWithExtension(const std::string& extension, const std::string& explanation);
extern const CLI::Validator TextureOutputFile;  //!< a texture file's name: .ply

}  // namespace geotex::cli
