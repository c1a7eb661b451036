// End-to-end tests of the geotex command line: help, errors, and the foundation commands.

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "geotex/core/io.h"
#include "geotex/tools/metrics.h"
#include "test_util.h"

using geotex::test::run_cli;
using geotex::test::TempDir;

namespace {
int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }
}  // namespace

TEST(Cli, EveryCommandHasHelp) {
  const auto top = run_cli("--help");
  EXPECT_EQ(top.exit_code, 0);
  for (const char* cmd : {"info", "generate", "noise", "smooth", "compare", "demo", "denoise"}) {
    EXPECT_NE(top.out.find(cmd), std::string::npos) << cmd;
    const auto r = run_cli(std::string(cmd) + " --help");
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << cmd;
  }
}

// The README's exit codes: 1 for bad input or files (a missing input, a folder, an unknown extension),
// 2 for bad flags, whichever command reads the file.
TEST(Cli, AMissingInputIsAFileErrorNotAFlagError) {
  TempDir tmp;
  for (const std::string& c : {"info " + (tmp / "missing.obj"), "denoise " + (tmp / "missing.obj") + " -o " + (tmp / "o.ply"),
                               "info " + tmp.path.string(), "texture apply " + (tmp / "missing.ply") + " -o " + (tmp / "o.ply"),
                               "info " + (tmp / "mesh.xyz")}) {
    const auto r = run_cli(c);
    EXPECT_EQ(r.exit_code, 1) << c << ": " << r.err;
    EXPECT_NE(r.err.find("file error"), std::string::npos) << c << ": " << r.err;
  }
  geotex::test::write_file(tmp / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(run_cli("smooth " + (tmp / "t.obj") + " -o " + (tmp / "o.obj") + " --laplacian fancy").exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(tmp / "o.ply"));
}

TEST(Cli, ErrorsAreOneLineAndNonZero) {
  TempDir tmp;
  geotex::test::write_file(tmp / "bad.obj", "v 0 0 0\nv 1 0 nope\n");
  geotex::test::write_file(tmp / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  const std::string cases[] = {
      "info " + (tmp / "missing.obj"),
      "info " + (tmp / "bad.obj"),
      "info " + (tmp / "nan.obj"),
      "smooth " + (tmp / "bad.obj") + " -o " + (tmp / "out.obj"),
      "generate teapot -o " + (tmp / "t.obj"),
      "generate cube",                                   // missing -o
      "noise " + (tmp / "nan.obj") + " -o " + (tmp / "o.obj") + " --sigma -1",
      "smooth " + (tmp / "nan.obj") + " -o " + (tmp / "o.obj") + " --laplacian fancy",
      "nosuchcommand",
  };
  for (const auto& c : cases) {
    const auto r = run_cli(c);
    EXPECT_NE(r.exit_code, 0) << c;
    EXPECT_EQ(count_lines(r.err), 1) << c << "\n" << r.err;
    EXPECT_NE(r.err.find("geotex: "), std::string::npos) << c << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(tmp / "out.obj"));
  }
}

TEST(Cli, GenerateNoiseSmoothCompare) {
  TempDir tmp;
  ASSERT_EQ(run_cli("generate cube --level 1 -o " + (tmp / "c.ply")).exit_code, 0);
  ASSERT_EQ(run_cli("noise " + (tmp / "c.ply") + " -o " + (tmp / "n.obj") + " --sigma 0.2 --seed 3").exit_code, 0);
  ASSERT_EQ(run_cli("smooth " + (tmp / "n.obj") + " -o " + (tmp / "s.off") + " --steps 1 --lambda 0.2").exit_code, 0);
  const auto before = run_cli("compare " + (tmp / "n.obj") + " " + (tmp / "c.ply") + " --json");
  const auto after = run_cli("compare " + (tmp / "s.off") + " " + (tmp / "c.ply") + " --json");
  ASSERT_EQ(before.exit_code, 0) << before.err;
  ASSERT_EQ(after.exit_code, 0) << after.err;
  const auto jb = nlohmann::json::parse(before.out), ja = nlohmann::json::parse(after.out);
  for (const char* k : {"mean_normal_error_deg", "ev", "ev_relative", "hausdorff", "hausdorff_relative"}) {
    EXPECT_TRUE(ja.contains(k)) << k;
  }
  EXPECT_LT(ja["mean_normal_error_deg"].get<double>(), jb["mean_normal_error_deg"].get<double>());
  // The JSON agrees with the library.
  const auto c = geotex::compare_meshes(geotex::read_mesh(tmp / "s.off"), geotex::read_mesh(tmp / "c.ply"));
  EXPECT_DOUBLE_EQ(ja["mean_normal_error_deg"].get<double>(), c.mean_normal_error_deg);
  // Text output has the normal error with at least two decimals.
  const auto text = run_cli("compare " + (tmp / "s.off") + " " + (tmp / "c.ply"));
  EXPECT_NE(text.out.find("deg"), std::string::npos);
  EXPECT_NE(text.out.find("Ev"), std::string::npos);
  EXPECT_NE(text.out.find("Hausdorff"), std::string::npos);
}

TEST(Cli, InputIsNeverDamaged) {
  TempDir tmp;
  ASSERT_EQ(run_cli("generate sphere --level 0 -o " + (tmp / "s.obj")).exit_code, 0);
  const std::string before = geotex::test::read_file(tmp / "s.obj");
  // Output into a folder that does not exist: error, input untouched.
  EXPECT_NE(run_cli("smooth " + (tmp / "s.obj") + " -o " + (tmp / "no/dir/out.obj")).exit_code, 0);
  EXPECT_EQ(geotex::test::read_file(tmp / "s.obj"), before);
}

TEST(Cli, InfoJsonGivesTheTopology) {
  TempDir tmp;
  ASSERT_EQ(run_cli("generate torus --level 0 -o " + (tmp / "t.ply")).exit_code, 0);
  const auto r = run_cli("info --json " + (tmp / "t.ply"));
  ASSERT_EQ(r.exit_code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["genus"].get<int>(), 1);
  EXPECT_EQ(j["euler_characteristic"].get<int>(), 0);
  EXPECT_EQ(j["boundary_loops"].get<int>(), 0);
  EXPECT_TRUE(j["manifold"].get<bool>());
}

TEST(CliData, InfoAndCompareOnEverySharedMesh) {
  GEOTEX_REQUIRE_DATA();
  const auto dir = geotex::test::data_dir();
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    const auto ext = e.path().extension().string();
    if (ext != ".obj" && ext != ".ply") continue;
    const auto r = run_cli("-q info --json " + e.path().string());
    EXPECT_EQ(r.exit_code, 0) << e.path() << "\n" << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["faces"].get<int>(), 0) << e.path();
  }
  for (const char* pair : {"Fandisk0.3", "Block0.4", "Twelve0.5Impulsive", "Bunny0.2"}) {
    const auto base = dir / "denoise" / pair;
    const auto r = run_cli("compare --json " + (base / "Noisy.obj").string() + " " + (base / "Original.obj").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["mean_normal_error_deg"].get<double>(), 1.0) << pair;
    EXPECT_EQ(j["faces_matched_by"].get<std::string>(), "index");
  }
}

TEST(Cli, DemoWritesItsFolder) {
  TempDir tmp;
  const auto r = run_cli("-q demo --only shapes --only \"noise and smoothing\" -o " + (tmp / "demo"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(tmp / "demo/report.json"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "demo/cube-noisy.ply"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "demo/spiky-sphere.ply"));
  // A caption says the figures of the step's report record, by the report's names (results.h: figures()).
  const auto report = nlohmann::json::parse(geotex::test::read_file(tmp / "demo/report.json"));
  int checked = 0;
  for (const auto& step : report["steps"]) {
    if (step["name"] != "noise and smoothing") continue;
    for (const char* method : {"umbrella", "cotan"}) {
      const double error = step[method]["mean_normal_error_deg"].get<double>();
      const std::string said = fmt::format("mean normal error {:.3g} deg", error);
      bool found = false;
      for (const auto& f : step["figures"])
        found = found || f["caption"].get<std::string>().find(said) != std::string::npos;
      EXPECT_TRUE(found) << method << ": no caption says '" << said << "'";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 2);
}

// The "wrote NAME" line is one line whatever the name (issue 30): ESC and a newline in an output name are
// shown escaped, as error lines show them; the file gets the name as given.
TEST(Cli, AnOutputNameWithControlBytesIsEchoedEscaped) {
  TempDir tmp;
  const std::string name = std::string("a\x1b[31m") + "\n" + "b.ply";
  const auto r = run_cli("generate cube --level 1 -o '" + (tmp / name) + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(tmp.path / name));
  EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\\x1b[31m\\x0ab.ply"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}
