// The command line as a user meets it (issue 28): quiet logs, "did you mean" for a mistyped flag or
// command, output names refused before any work, help texts that list what exists.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.h"

using geotex::test::run_cli;
using geotex::test::TempDir;

namespace {
std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> lines;
  std::istringstream in(s);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// The names listed under "Subcommands:" in a --help text.
std::vector<std::string> subcommands_in_help(const std::string& help) {
  std::vector<std::string> names;
  bool in = false;
  for (const auto& line : lines_of(help)) {
    if (line == "Subcommands:") in = true;
    else if (in && starts_with(line, "  ") && line.size() > 2 && line[2] != ' ') names.push_back(line.substr(2, line.find(' ', 2) - 2));
    else if (in && !line.empty()) in = false;
  }
  return names;
}

// A small noisy cube with one vertex in no face (a reader warning on every run).
std::string noisy_cube_with_warning(const TempDir& tmp) {
  EXPECT_EQ(run_cli("generate cube --level 1 -o " + (tmp / "c.obj")).exit_code, 0);
  EXPECT_EQ(run_cli("noise " + (tmp / "c.obj") + " -o " + (tmp / "n.obj") + " --sigma 0.2").exit_code, 0);
  std::ofstream(tmp / "n.obj", std::ios::app) << "v 5 5 5\n";
  return tmp / "n.obj";
}
}  // namespace

// stderr is a file here: a run that ends within seconds prints no progress line, only what it found,
// its warnings and what it wrote.
TEST(CliHints, ShortRunsPrintNoProgressLinesToALog) {
  TempDir tmp;
  const std::string in = noisy_cube_with_warning(tmp);
  for (const std::string& c : {"denoise " + in + " -o " + (tmp / "d.ply") + " --edges " + (tmp / "e.ply"),
                               "denoise " + in + " -o " + (tmp / "m.ply") + " --method mrf",
                               "smooth " + in + " -o " + (tmp / "s.ply") + " --steps 3"}) {
    const auto r = run_cli(c);
    ASSERT_EQ(r.exit_code, 0) << c << "\n" << r.err;
    bool warned = false, wrote = false;
    for (const auto& line : lines_of(r.err)) {
      EXPECT_FALSE(starts_with(line, "denoise ") || starts_with(line, "smooth:")) << c << ": a progress line: " << line;
      EXPECT_EQ(line.find('\r'), std::string::npos) << c;
      warned = warned || (starts_with(line, "geotex: warning: ") && line.find("belong to no face") != std::string::npos);
      wrote = wrote || starts_with(line, "wrote ");
    }
    EXPECT_TRUE(warned) << c << "\n" << r.err;
    EXPECT_TRUE(wrote) << c << "\n" << r.err;
  }
}

TEST(CliHints, AMistypedFlagNamesTheClosestOne) {
  TempDir tmp;
  const std::string in = noisy_cube_with_warning(tmp), out = tmp / "o.ply";
  struct Case {
    std::string args, message;
  };
  const Case cases[] = {
      {"denoise " + in + " -o " + out + " --sigmaa 0.2", "geotex: error: unknown flag --sigmaa (did you mean --sigma?)"},
      {"denoise " + in + " -o " + out + " --sigmaa=0.2", "geotex: error: unknown flag --sigmaa (did you mean --sigma?)"},
      // The value after the unknown flag shifts into IN ("0.2: no such file"): the flag is still the error named.
      {"denoise --sigmaa 0.2 " + in + " -o " + out, "geotex: error: unknown flag --sigmaa (did you mean --sigma?)"},
      {"denoise " + in + " -o " + out + " --lable-threshold 0.3",
       "geotex: error: unknown flag --lable-threshold (did you mean --label-threshold?)"},
      {"--quite info " + in, "geotex: error: unknown flag --quite (did you mean --quiet?)"},
      {"info " + in + " --jsn", "geotex: error: unknown flag --jsn (did you mean --json?)"},
      {"smooth " + in + " -o " + out + " --lamda 0.1", "geotex: error: unknown flag --lamda (did you mean --lambda?)"},
      {"denoise " + in + " -o " + out + " --zzzzzzzz", "geotex: error: unknown flag --zzzzzzzz (see geotex denoise --help)"},
      {"denoize " + in + " -o " + out, "geotex: error: unknown command denoize (did you mean denoise?)"},
      {"texture synthesise " + in + " --target " + in + " -o " + out,
       "geotex: error: unknown texture command synthesise (did you mean synthesize?)"},
      {"frobnicate", "geotex: error: unknown command frobnicate (see geotex --help)"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err, c.message + "\n") << c.args;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
  // A flag of the right name but a bad value is still reported as such.
  const auto r = run_cli("denoise " + in + " -o " + out + " --sigma -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("out of range"), std::string::npos) << r.err;
}

// An output name no writer takes is refused while the command line is read: before the input is loaded,
// so at once even for a mesh that takes seconds to denoise, and nothing is written.
TEST(CliHints, BadOutputNamesAreRefusedBeforeAnyWork) {
  TempDir tmp;
  const std::string in = noisy_cube_with_warning(tmp);
  ASSERT_EQ(run_cli("generate spiky-plane --level 0 -o " + (tmp / "sp.ply") + " --base-output " + (tmp / "spb.ply")).exit_code, 0);
  struct Case {
    std::string args, says;
  };
  const Case cases[] = {
      {"denoise " + in + " -o " + (tmp / "x.ply.gz"), "x.ply.gz: geotex reads gzipped meshes but does not write them"},
      {"denoise " + in + " -o " + (tmp / "d.ply") + " --edges " + (tmp / "e.obj"), "--edges-obj"},
      {"denoise " + in + " -o " + (tmp / "d.ply") + " --edges-obj " + (tmp / "e.ply"), "--edges-obj writes OBJ"},
      {"denoise " + in + " -o " + (tmp / "d.ply") + " --method surfel --polygons " + (tmp / "p.ply"), "--polygons writes OBJ"},
      {"smooth " + in + " -o " + (tmp / "x.3mf"), "unknown mesh format '.3mf'"},
      {"generate cube -o " + (tmp / "x.dae"), "unknown mesh format '.dae'"},
      {"generate spiky-plane -o " + (tmp / "g.ply") + " --base-output " + (tmp / "b.fbx"), "unknown mesh format '.fbx'"},
      {"texture extract " + (tmp / "sp.ply") + " --base " + (tmp / "spb.ply") + " -o " + (tmp / "t.obj"), "a texture file is a PLY"},
      {"texture extract " + (tmp / "sp.ply") + " --base " + (tmp / "spb.ply") + " -o " + (tmp / "t.ply") + " --reconstructed " +
           (tmp / "r.usdz"),
       "unknown mesh format '.usdz'"},
      {"project " + in + " " + in + " -o " + (tmp / "x.fbx"), "unknown mesh format '.fbx'"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("geotex: file error: ", 0), 0u) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args << "\n" << r.err;  // no warning: IN is not read
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
  }
  for (const char* f : {"d.ply", "e.obj", "e.ply", "p.ply", "x.ply.gz", "g.ply", "t.obj", "t.ply"})
    EXPECT_FALSE(std::filesystem::exists(tmp / f)) << f;
}

TEST(CliHints, HelpListsEverySubcommandAndNoSourceFile) {
  const auto top = run_cli("--help");
  ASSERT_EQ(top.exit_code, 0);
  const std::vector<std::string> commands = subcommands_in_help(top.out);
  ASSERT_GE(commands.size(), 10u) << top.out;
  const auto texture = run_cli("texture --help");
  ASSERT_EQ(texture.exit_code, 0);
  const std::vector<std::string> texture_commands = subcommands_in_help(texture.out);
  ASSERT_GE(texture_commands.size(), 7u) << texture.out;
  // The description (first line of `texture --help`, and texture's line in `geotex --help`) names them all.
  std::string texture_line;
  for (const auto& line : lines_of(top.out))
    if (starts_with(line, "  texture ")) texture_line = line;
  for (const auto& s : texture_commands) {
    EXPECT_NE(lines_of(texture.out).front().find(s), std::string::npos) << s << "\n" << texture.out;
    EXPECT_NE(texture_line.find(s), std::string::npos) << s << "\n" << texture_line;
  }
  EXPECT_NE(std::find(texture_commands.begin(), texture_commands.end(), "synthesize"), texture_commands.end());

  std::vector<std::string> all;
  for (const auto& c : commands)
    if (c != "texture") all.push_back(c);
  for (const auto& s : texture_commands) all.push_back("texture " + s);
  for (const auto& c : all) {
    const auto r = run_cli(c + " --help");
    EXPECT_EQ(r.exit_code, 0) << c;
    for (const char* source : {".cpp", ".h)", ".h ", "src/", "apps/"})
      EXPECT_EQ(r.out.find(source), std::string::npos) << c << " --help points to a source file:\n" << r.out;
  }
  // deform's handles file is described where the user looks for it.
  const auto deform = run_cli("deform --help");
  for (const char* key : {"\"vertices\"", "\"sphere\"", "\"box\"", "\"targets\"", "\"translate\"", "\"rotate\"", "\"scale\"", "\"weight\""})
    EXPECT_NE(deform.out.find(key), std::string::npos) << key;
}

// README's command table has a row for every command (and texture subcommand) of `geotex --help`.
TEST(CliHints, ReadmeTableHasEveryCommand) {
  std::ifstream readme(std::filesystem::path(geotex::test::source_dir()) / "README.md");
  ASSERT_TRUE(readme) << "README.md not found";
  std::set<std::string> rows;
  for (std::string line; std::getline(readme, line);) {
    if (!starts_with(line, "| `geotex ")) continue;
    std::istringstream words(line.substr(10));
    std::string name, sub;
    words >> name >> sub;
    rows.insert(name);
    if (name == "texture") rows.insert("texture " + sub);
  }
  for (const auto& c : subcommands_in_help(run_cli("--help").out)) EXPECT_TRUE(rows.count(c)) << "no README row for geotex " << c;
  for (const auto& s : subcommands_in_help(run_cli("texture --help").out))
    EXPECT_TRUE(rows.count("texture " + s)) << "no README row for geotex texture " << s;
}
