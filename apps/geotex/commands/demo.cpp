// geotex demo [-o DIR]: run every capability on generated shapes and write the results to a folder.
// Each capability contributes a step from its own demo_*.cpp file (see DemoRegistrar in cli.h).

#include <algorithm>
#include <chrono>
#include <filesystem>

#include <fmt/format.h>

#include "cli.h"

namespace geotex::cli {
namespace cmd_demo {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string dir = "geotex-demo";
  std::vector<std::string> only;
  bool quick = false;
#ifdef GEOTEX_DEMO_DATA
  std::string data = GEOTEX_DEMO_DATA;
#else
  std::string data;
#endif
};

}  // namespace cmd_demo

std::filesystem::path shipped_data_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) candidates = {exe.parent_path().parent_path() / "share" / "geotex" / "data", exe.parent_path().parent_path() / "data"};
#ifdef GEOTEX_SHIPPED_DATA
  candidates.emplace_back(GEOTEX_SHIPPED_DATA);
#endif
  for (const fs::path& c : candidates)
    if (fs::is_regular_file(c / "spot.obj", ec)) return c;
  return {};
}

std::filesystem::path demo_model(const DemoContext& ctx, const std::string& name) {
  std::error_code ec;
  for (const auto& dir : {ctx.data, ctx.shipped})
    if (!dir.empty() && std::filesystem::is_regular_file(dir / name, ec)) return dir / name;
  return {};
}

namespace cmd_demo {

void run(const Args& a) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(a.dir, ec);
  if (ec || !fs::is_directory(a.dir)) throw IoError(fmt::format("{}: cannot create the output folder", a.dir));
  auto& steps = demo_steps();
  std::sort(steps.begin(), steps.end(), [](const DemoStep& x, const DemoStep& y) { return x.order < y.order; });
  nlohmann::json report;
  report["steps"] = nlohmann::json::array();
  const auto t_all = std::chrono::steady_clock::now();
  size_t k = 0;
  for (const auto& s : steps) {
    ++k;
    if (!a.only.empty() && std::find(a.only.begin(), a.only.end(), s.name) == a.only.end()) continue;
    info(fmt::format("[{}/{}] {}", k, steps.size(), s.name));
    const auto t0 = std::chrono::steady_clock::now();
    nlohmann::json section;
    s.run({fs::path(a.dir), &section, &report["steps"], a.quick, a.quick ? fs::path() : fs::path(a.data),
           a.quick ? fs::path() : shipped_data_dir()});
    section["section"] = demo_section(s.order);
    section["name"] = s.name;
    section["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    report["steps"].push_back(section);
  }
  report["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_all).count();
  write_text_atomic(fs::path(a.dir) / "report.json", report.dump(2) + "\n");
  // A short human-readable summary beside the JSON.
  std::string md = "# geotex demo\n\n";
  for (const auto& s : report["steps"]) {
    md += fmt::format("## {}\n\n", s["name"].get<std::string>());
    if (s.contains("summary"))
      for (const auto& line : s["summary"]) md += "- " + line.get<std::string>() + "\n";
    md += "\n";
  }
  write_text_atomic(fs::path(a.dir) / "README.md", md);
  fmt::print("demo finished in {:.1f} s; results in {}/ (README.md, report.json)\n", report["seconds"].get<double>(), a.dir);
}

Registrar reg{1000, "demo", "Run the whole pipeline on generated shapes, writing results to a folder", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("-o,--output", a->dir, "output folder (created)")->capture_default_str();
  app.add_option("--only", a->only, "run only the named steps");
  app.add_flag("--quick", a->quick, "coarse shapes and no real model (a quick check of the whole pipeline)");
  app.add_option("--data", a->data, "folder of the shared meshes (denoise/Fandisk0.3 and cow.obj are shown when present; the shipped "
                 "spot.obj always)")
      ->capture_default_str();
  app.callback([a] { run(*a); });
}};

}  // namespace cmd_demo
}  // namespace geotex::cli
