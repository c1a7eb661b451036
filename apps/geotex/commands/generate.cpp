// geotex generate SHAPE -o OUT: procedural test shapes.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace cmd_generate {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string shape, output, base_output;
  int level = 1;
  uint64_t seed = 1;
};

void run(const Args& a) {
  Outputs out({}, {{a.output, "-o"}, {a.base_output, "--base-output"}});
  const TexturedShape s = make_shape(a.shape, a.level, a.seed);
  save_mesh(s.textured, a.output);
  if (!a.base_output.empty()) save_mesh(s.base, a.base_output);
  out.commit();
}

Registrar reg{20, "generate", "Write a procedural test shape (see SHAPE for the names)",
              [](CLI::App& app) {
                auto a = std::make_shared<Args>();
                app.add_option("SHAPE", a->shape, "shape name")->required()->check(CLI::IsMember(shape_names()));
                app.add_option("-o,--output", a->output, "output mesh file (- writes standard output, in the format of --format)")
                    ->required()->check(MeshOutputFile);
                app.add_option("--level", a->level, "resolution level: 0 coarse, 1 default, each level ~4x the faces")
                    ->check(CLI::Range(0, 8))->capture_default_str();
                app.add_option("--seed", a->seed, "seed for the spiky shapes")->capture_default_str();
                app.add_option("--base-output", a->base_output, "also write the untextured base (spiky shapes)")
                    ->check(MeshOutputFile);
                app.callback([a] { run(*a); });
              }};

}  // namespace cmd_generate
}  // namespace geotex::cli
