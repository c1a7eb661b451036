// `geotex texture …` on the command line: flags made from the option tables, round trips through
// files, options refused before any work, outputs that name an input refused.

#include <filesystem>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::read_file;
using geotex::test::run_cli;
using geotex::test::TempDir;
using geotex::test::write_file;

namespace {

double max_error(const Mesh& a, const Mesh& b) { return (positions(a) - positions(b)).rowwise().norm().maxCoeff(); }

// A spiky sphere (leaning spikes no height field holds), its base, and its texture against that base.
struct Files {
  TempDir dir;
  std::string textured = dir / "s.ply", base = dir / "b.ply", texture = dir / "t.ply";
  Files() {
    EXPECT_EQ(run_cli("-q generate spiky-sphere --level 0 -o " + textured + " --base-output " + base).exit_code, 0);
    const auto r = run_cli("-q texture extract " + textured + " --base " + base + " -o " + texture);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
};

// Every option of \p table appears as its flag in \p help.
template <class O>
void expect_every_flag(const std::string& help, const OptionTable<O>& table, const std::string& what) {
  for (const auto& f : table.fields()) EXPECT_NE(help.find(f.info.cli_flag()), std::string::npos) << what << " " << f.info.cli_flag();
  EXPECT_EQ(help.find("--preset") != std::string::npos, !table.presets().empty()) << what;
}

}  // namespace

TEST(TextureCli, EveryOptionOfTheTablesIsAFlag) {
  expect_every_flag(run_cli("texture extract --help").out, TextureExtractOptions::table(), "extract");
  expect_every_flag(run_cli("texture apply --help").out, TextureApplyOptions::table(), "apply");
  expect_every_flag(run_cli("texture edit --help").out, TextureEditOptions::table(), "edit");
  expect_every_flag(run_cli("texture animate --help").out, AnimationOptions::table(), "animate");
  expect_every_flag(run_cli("texture transfer --help").out, TransferOptions::table(), "transfer");
  expect_every_flag(run_cli("texture atlas --help").out, AtlasOptions::table(), "atlas");
  // Defaults, ranges and thesis references come with them.
  const std::string help = run_cli("texture transfer --help").out;
  EXPECT_NE(help.find("default 0.4"), std::string::npos) << help;      // --falloff
  EXPECT_NE(help.find("in [0, 1]"), std::string::npos) << help;
  EXPECT_NE(help.find("patch-radius|absolute"), std::string::npos) << help;
  EXPECT_NE(run_cli("texture --help").out.find("atlas"), std::string::npos);
  EXPECT_NE(run_cli("texture").exit_code, 0);
}

TEST(TextureCli, OptionsCommandListsTheTextureSubcommands) {
  const auto r = run_cli("options");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const std::pair<const char*, size_t> expected[] = {
      {"extract", TextureExtractOptions::table().fields().size()}, {"apply", TextureApplyOptions::table().fields().size()},
      {"edit", TextureEditOptions::table().fields().size()},       {"animate", AnimationOptions::table().fields().size()},
      {"transfer", TransferOptions::table().fields().size()},      {"atlas", AtlasOptions::table().fields().size()}};
  for (const auto& [sub, n] : expected) {
    const std::string command = std::string("texture ") + sub;
    ASSERT_TRUE(j.contains(command)) << command;
    ASSERT_TRUE(j[command].contains(sub)) << command;
    EXPECT_EQ(j[command][sub].size(), n) << command;
  }
  EXPECT_EQ(j["texture transfer"]["transfer"]["falloff"]["default"], "0.4");
  EXPECT_EQ(j["texture extract"]["extract"]["base_method"]["choices"], nlohmann::json({"robust", "smoothing", "thesis"}));
}

TEST(TextureCli, ExtractThenApplyRebuildsTheMesh) {
  Files f;
  const Mesh textured = read_mesh(f.textured);
  const double h = mean_edge_length(read_mesh(f.base));
  auto r = run_cli("texture apply " + f.texture + " -o " + (f.dir / "a.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(max_error(read_mesh(f.dir / "a.ply"), textured), 1e-3 * h);
  // Through every tilt fit: flags from the table reach the library.
  for (const std::string flags : {"--tilt-solver direct", "--no-tangential-fit --tilt-solver direct"}) {
    r = run_cli("texture extract " + f.textured + " --base " + f.base + " -o " + (f.dir / "t2.ply") + " " + flags +
                " --reconstructed " + (f.dir / "r.ply"));
    ASSERT_EQ(r.exit_code, 0) << flags << "\n" << r.err;
    EXPECT_LT(max_error(read_mesh(f.dir / "r.ply"), textured), 1e-3 * h) << flags;
    EXPECT_NE(r.err.find("tilt fit: direct"), std::string::npos) << r.err;
  }
  // The thesis' encoding (no lean stored; its bound on the tilt costs accuracy on these spikes).
  r = run_cli("texture extract " + f.textured + " --base " + f.base + " -o " + (f.dir / "t2.ply") + " --preset thesis");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_texture(f.dir / "t2.ply").texture.lean.size(), 0);
  // The automatic base, as the thesis' smoothing (--steps) and as the robust fit.
  for (const std::string flags : {"--steps 3", "--base-method robust --robust-passes 1"}) {
    r = run_cli("texture extract " + f.textured + " -o " + (f.dir / "t3.ply") + " " + flags + " --reconstructed " +
                (f.dir / "r3.ply"));
    ASSERT_EQ(r.exit_code, 0) << flags << "\n" << r.err;
    EXPECT_NE(r.err.find(flags == "--steps 3" ? "smoothing, 3 step(s)" : "robust fit"), std::string::npos) << r.err;
    EXPECT_LT(max_error(read_mesh(f.dir / "r3.ply"), textured), 1e-3 * h) << flags;
  }
  // --height-scale 2 doubles every displacement along the normal (a zero tilt leaves only heights).
  r = run_cli("texture apply " + f.texture + " -o " + (f.dir / "h1.ply") + " --height-only");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("texture apply " + f.texture + " -o " + (f.dir / "h2.ply") + " --height-only --height-scale 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const MatrixX3d B = positions(read_mesh(f.base));
  const MatrixX3d D1 = positions(read_mesh(f.dir / "h1.ply")) - B, D2 = positions(read_mesh(f.dir / "h2.ply")) - B;
  EXPECT_LT((D2 - 2 * D1).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT(D1.cwiseAbs().maxCoeff(), 2 * h);
}

TEST(TextureCli, EditAnimateThroughTheFlags) {
  Files f;
  const TextureFile t = read_texture(f.texture);
  auto r = run_cli("texture edit " + f.texture + " -o " + (f.dir / "e.ply") + " --op scale-height --factor 3 --mesh " +
                   (f.dir / "m.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT((read_texture(f.dir / "e.ply").texture.height - 3 * t.texture.height).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(read_mesh(f.dir / "m.ply").n_vertices(), t.base.n_vertices());
  r = run_cli("texture edit " + f.texture + " -o " + (f.dir / "e.ply") + " --op set-tilt --angle 0 --direction 0,0,1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Texture upright = read_texture(f.dir / "e.ply").texture;
  EXPECT_LT(upright.lean.cwiseAbs().maxCoeff(), 1e-9);  // lean 0: every displacement along its normal
  // Frames: grow starts at the bare base (heights × 0) and the files are numbered.
  r = run_cli("texture animate " + f.texture + " -o " + (f.dir / "fr") + " --op grow --frames 3 --format obj");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"fr_0000.obj", "fr_0001.obj", "fr_0002.obj"}) EXPECT_TRUE(std::filesystem::exists(f.dir / name)) << name;
  EXPECT_FALSE(std::filesystem::exists(f.dir / "fr_0003.obj"));
  EXPECT_LT(max_error(read_mesh(f.dir / "fr_0000.obj"), read_mesh(f.base)), 1e-6);
}

TEST(TextureCli, TransferAndAtlasThroughTheFlags) {
  TempDir dir;
  ASSERT_EQ(run_cli("-q generate bumpy-plate --level 0 -o " + (dir / "p.ply") + " --base-output " + (dir / "pb.ply")).exit_code, 0);
  ASSERT_EQ(run_cli("-q generate sphere --level 1 -o " + (dir / "s.ply")).exit_code, 0);
  auto r = run_cli("-q texture extract " + (dir / "p.ply") + " --base " + (dir / "pb.ply") + " -o " + (dir / "t.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("texture transfer " + (dir / "t.ply") + " " + (dir / "s.ply") + " -o " + (dir / "out.ply") +
              " --source-near 0,0,0 --source-radius 0.5 --target-near 0,0,1 --target-radius 0.5 --falloff 0.3 "
              "--refine-ratio 0 --texture-out " + (dir / "out-t.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const TextureFile tt = read_texture(dir / "out-t.ply");
  EXPECT_EQ(tt.base.n_vertices(), read_mesh(dir / "s.ply").n_vertices());  // --refine-ratio 0: never refined
  EXPECT_GT(tt.texture.height.cwiseAbs().maxCoeff(), 0);
  // Heights only near the target point (the patch), none on the far side.
  const MatrixX3d X = positions(tt.base);
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (X(i, 2) < 0) EXPECT_EQ(tt.texture.height[i], 0) << i;
  r = run_cli("texture atlas " + (dir / "t.ply") + " " + (dir / "s.ply") + " -o " + (dir / "atlas.ply") +
              " --source-near 0,0,0 --source-radius 0.5 --target-radius 0.7 --refine-ratio 0 --texture-out " +
              (dir / "atlas-t.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("0 vertices uncovered"), std::string::npos) << r.err;
  EXPECT_EQ(read_mesh(dir / "atlas.ply").n_vertices(), read_mesh(dir / "s.ply").n_vertices());
  // The source centre: a vertex or a point, not both; the radii must be given.
  r = run_cli("texture transfer " + (dir / "t.ply") + " " + (dir / "s.ply") + " -o " + (dir / "x.ply") +
              " --source-center 0 --source-near 0,0,0 --source-radius 0.5 --target-radius 0.5");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = run_cli("texture atlas " + (dir / "t.ply") + " " + (dir / "s.ply") + " -o " + (dir / "x.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--source-radius"), std::string::npos) << r.err;
  r = run_cli("texture transfer " + (dir / "t.ply") + " " + (dir / "s.ply") + " -o " + (dir / "x.ply") +
              " --source-center 0 --source-radius 0.3 --target-center 999999 --target-radius 0.3");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("out of range"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.ply"));
}

// A bad value, a flag of another subcommand or an option that does not apply: exit 2, before any
// file is read or written (an existing output keeps its bytes).
TEST(TextureCli, BadFlagsAreRefusedBeforeAnyWork) {
  Files f;
  const std::string out = f.dir / "out.ply", sphere = f.dir / "sp.ply";
  ASSERT_EQ(run_cli("-q generate sphere --level 0 -o " + sphere).exit_code, 0);
  write_file(out, "keep me");
  const std::string t = f.texture, s = f.textured;
  const std::string bad[] = {
      "texture extract " + s + " -o " + out + " --lambda -1",
      "texture extract " + s + " -o " + out + " --tilt-solver cholesky",
      "texture extract " + s + " -o " + out + " --fit-tolerance 0",
      "texture extract " + s + " -o " + out + " --base " + f.base + " --base-scale 5",  // automatic base only
      "texture extract " + s + " -o " + out + " --project-onto-base",                   // needs --base
      "texture extract " + s + " -o " + out + " --preset best",
      "texture apply " + t + " -o " + out + " --height-scale nan",
      "texture apply " + t + " -o " + out + " --falloff 0.2",  // a transfer option
      "texture apply " + t + " -o " + out + " --preset thesis",  // apply has no presets
      "texture edit " + t + " -o " + out + " --op twist",
      "texture edit " + t + " -o " + out + " --direction 1,2",
      "texture edit " + t + " -o " + out + " --wavelength -1",
      "texture animate " + t + " -o " + (f.dir / "out") + " --frames 0",
      "texture animate " + t + " -o " + (f.dir / "out") + " --op spin",
      "texture transfer " + t + " " + sphere + " -o " + out + " --source-radius 1 --target-radius 1 --falloff 2",
      "texture transfer " + t + " " + sphere + " -o " + out + " --source-radius 1 --target-radius 1 --source-near 1,x,0",
      "texture atlas " + t + " " + sphere + " -o " + out + " --source-radius 1 --spacing 0",
      "texture atlas " + t + " " + sphere + " -o " + out + " --source-radius 1 --blend-power 0.5",
  };
  for (const auto& c : bad) {
    const auto r = run_cli(c);
    EXPECT_EQ(r.exit_code, 2) << c << "\n" << r.err;
    EXPECT_EQ(r.err.find("read texture"), std::string::npos) << c << ": read its input first\n" << r.err;
    EXPECT_EQ(read_file(out), "keep me") << c;
  }
  EXPECT_FALSE(std::filesystem::exists(f.dir / "out_0000.ply"));
  // The messages name the option.
  EXPECT_NE(run_cli(bad[1]).err.find("tilt_solver"), std::string::npos);
  EXPECT_NE(run_cli(bad[2]).err.find("fit_tolerance"), std::string::npos);
  EXPECT_NE(run_cli(bad[3]).err.find("--base-scale"), std::string::npos);
  EXPECT_NE(run_cli(bad[10]).err.find("direction"), std::string::npos);
}

// An output that names an input (or is the same file by another path) is refused before any work,
// and the input keeps its bytes: `texture apply T -o T` must not lose the texture.
TEST(TextureCli, OutputThatIsAnInputIsRefused) {
  Files f;
  const std::string texture = read_file(f.texture), textured = read_file(f.textured);
  ASSERT_EQ(run_cli("-q generate sphere --level 0 -o " + (f.dir / "sp.ply")).exit_code, 0);
  const std::string same[] = {
      "texture apply " + f.texture + " -o " + f.texture,
      "texture apply " + f.texture + " -o " + (f.dir / "./t.ply"),
      "texture apply " + f.texture + " -o " + (f.dir / "a.ply") + " --base " + (f.dir / "a.ply"),
      "texture edit " + f.texture + " -o " + f.texture,
      "texture edit " + f.texture + " -o " + (f.dir / "e.ply") + " --mesh " + f.texture,
      "texture extract " + f.textured + " -o " + f.textured,
      "texture extract " + f.textured + " --base " + f.base + " -o " + (f.dir / "x.ply") + " --reconstructed " + f.base,
      "texture transfer " + f.texture + " " + f.textured + " -o " + f.textured +
          " --source-radius 0.5 --target-radius 0.5",
      "texture atlas " + f.texture + " " + (f.dir / "sp.ply") + " -o " + (f.dir / "o.ply") + " --texture-out " +
          f.texture + " --source-radius 0.5",
  };
  write_file(f.dir / "a.ply", textured);
  for (const auto& c : same) {
    const auto r = run_cli(c);
    EXPECT_EQ(r.exit_code, 1) << c << "\n" << r.err;
    EXPECT_NE(r.err.find("input"), std::string::npos) << c << "\n" << r.err;
    EXPECT_EQ(r.err.find("read texture"), std::string::npos) << c << "\n" << r.err;
  }
  EXPECT_EQ(read_file(f.texture), texture);
  EXPECT_EQ(read_file(f.textured), textured);
  EXPECT_EQ(read_file(f.dir / "a.ply"), textured);
}

// A file that is not a texture: one line, exit 1, nothing written.
TEST(TextureCli, ApplyRefusesAMeshWithoutHeights) {
  Files f;
  const auto r = run_cli("texture apply " + f.textured + " -o " + (f.dir / "x.ply"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("height"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(f.dir / "x.ply"));
}
