// geotex: the command-line tool. Each subcommand lives in its own file and registers itself.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

#include <fmt/format.h>
#include <omp.h>

#include "cli.h"
#include "geotex/core/error.h"
#include "geotex/core/options.h"
#include "geotex/core/resources.h"

namespace {
// An error message as one printable line: messages may quote bytes from a broken file (binary garbage,
// terminal escape sequences, a newline in a token); those are shown as \xNN, and very long messages
// are cut, so the error stays one line that cannot disturb the terminal.
std::string one_line(const char* what) { return geotex::cli::printable(what, 1000); }
}  // namespace

namespace {
int run(int argc, char** argv);

// True when the address space is capped (ulimit -v, prlimit).
bool address_space_limited() {
  struct rlimit r {};
  return ::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY;
}
}  // namespace

int main(int argc, char** argv) {
#ifdef __linux__
  // OpenMP's idle threads spin before they sleep (libgomp's default): on a machine shared with other jobs that
  // spinning took a quarter of a synthesis' CPU time and made its wall time 1.7× longer (bench/synthesis.md,
  // issue 27). libgomp reads OMP_WAIT_POLICY before main, so when it is unset the tool runs itself again with
  // it passive (OMP_WAIT_POLICY=active keeps the spinning); if that fails, it goes on as it is.
  if (!std::getenv("OMP_WAIT_POLICY") && ::setenv("OMP_WAIT_POLICY", "passive", 1) == 0)
    ::execv("/proc/self/exe", argv);
#endif
  const int code = run(argc, argv);
  // Under an address-space cap, OpenBLAS's worker threads, started before main, may fail to map their
  // 128 MiB buffers and retry forever; its exit handler joins them, so geotex hung at exit after
  // finishing (issue 14, class 8: "spins forever inside BLAS"). Everything is written and closed by
  // now: leave without exit handlers.
  if (address_space_limited()) {
    std::fflush(nullptr);
    std::_Exit(code);
  }
  return code;
}

namespace {
// The one line and exit code of an error: 1 for bad input or files, 2 for bad flags, 3 for a bug.
int report_error(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "geotex: error: %s (see --help)\n", one_line(e.what()).c_str());
    return 2;
  } catch (const geotex::InvalidOption& e) {
    std::fprintf(stderr, "geotex: error: %s (see --help)\n", one_line(e.what()).c_str());
    return 2;
  } catch (const geotex::InvalidInput& e) {
    std::fprintf(stderr, "geotex: invalid input: %s\n", one_line(e.what()).c_str());
    return 1;
  } catch (const geotex::IoError& e) {
    std::fprintf(stderr, "geotex: file error: %s\n", one_line(e.what()).c_str());
    return 1;
  } catch (const geotex::SolverError& e) {
    std::fprintf(stderr, "geotex: solver error: %s\n", one_line(e.what()).c_str());
    return 1;
  } catch (const geotex::OutOfMemory& e) {
    std::fprintf(stderr, "geotex: out of memory: %s\n", one_line(e.what()).c_str());
    return 1;
  } catch (const geotex::Error& e) {
    std::fprintf(stderr, "geotex: error: %s\n", one_line(e.what()).c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "geotex: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geotex: internal error: %s\n", one_line(e.what()).c_str());
    return 3;
  } catch (...) {
    std::fprintf(stderr, "geotex: internal error: an unknown exception\n");
    return 3;
  }
}

int run(int argc, char** argv) {
  using namespace geotex::cli;
  geotex::set_blas_threads(1);  // OpenBLAS's spinning workers cost more than they give (resources.h)
  // Named, so that the usage line says "geotex", not the path the binary was started by.
  CLI::App app{"geotex: 3D shape modeling with high-level descriptors (after V. Andersen, DTU 2011)", "geotex"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "geotex 0.1.0");
  app.add_flag("-q,--quiet", globals().quiet, "no progress or warnings on stderr");
  app.add_option("--format", globals().stdout_format,
                 "format of a mesh written to standard output (-o -): ply, obj, off, stl, glb or gltf "
                 "(default ply; binary unless --ascii). An input - is standard input, its format read from its bytes")
      ->check(CLI::IsMember({"ply", "obj", "off", "stl", "glb", "gltf"}, CLI::ignore_case));
  int threads = 0;
  app.add_option("--threads", threads, "number of threads (default: all cores)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {  // a whole positive number (CLI11's checks let nan through)
            char* end = nullptr;
            const long v = std::strtol(s.c_str(), &end, 10);
            if (end == s.c_str() || *end != '\0' || v < 1 || v > 4096) return "'" + s + "' is not a number of threads (1 to 4096)";
            return {};
          },
          "N", "ThreadCount"))
      ->each([](const std::string& s) { omp_set_num_threads(static_cast<int>(std::strtol(s.c_str(), nullptr, 10))); });
  bool stats = false;
  app.add_flag("--stats", stats, "print wall time, CPU time and peak memory (resident set) on stderr at the end");
  // Printed on every exit path after parsing, errors included (e.g. to see how close a run came to
  // the memory limit), even with --quiet: the user asked for it.
  struct StatsAtExit {
    const bool& on;
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    ~StatsAtExit() {
      if (!on) return;
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, "geotex: stats: %.2f s wall, %.2f s cpu, peak memory %s (%zu KiB)\n", wall,
                   geotex::cpu_seconds(), geotex::format_bytes(geotex::peak_rss_bytes()).c_str(),
                   geotex::peak_rss_bytes() / 1024);
    }
  } stats_at_exit{stats};

  auto& cmds = commands();
  std::sort(cmds.begin(), cmds.end(), [](const Command& a, const Command& b) { return a.order < b.order; });
  // Global flags (-q, --threads, --stats) anywhere on the line: unknown options fall through to the app.
  for (auto& c : cmds) c.setup(*app.add_subcommand(c.name, c.help)->fallthrough());

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (...) {
    // A mistyped flag or command is the mistake to name, even when a validator failed first because
    // of it (its value shifted into IN) or a requirement is then missing.
    if (const auto message = unknown_argument_message(app)) {
      std::fprintf(stderr, "geotex: error: %s\n", one_line(message->c_str()).c_str());
      return 2;
    }
    return report_error(std::current_exception());
  }
  return 0;
}
}  // namespace
