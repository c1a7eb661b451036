// geotex noise IN -o OUT: seeded Gaussian (or impulsive) noise in mean-edge-length units.

#include "cli.h"
#include "geotex/tools/noise.h"
#include "option_flags.h"

namespace geotex::cli {
namespace cmd_noise {  // named, not anonymous: a unity build compiles several commands in one unit

Registrar reg{30, "noise", "Add seeded noise (sigma in units of the mean edge length)", [](CLI::App& app) {
  auto io = std::make_shared<MeshIo>(app);
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("noise", NoiseOptions::table());
  app.callback([io, flags] {
    const NoiseOptions o = flags->resolve<NoiseOptions>("noise");
    Outputs out({io->input}, {{io->output, "-o"}});
    Mesh mesh = load_mesh(io->input);
    set_positions(mesh, add_noise(mesh, o));
    save_mesh(mesh, io->output, !io->ascii);
    out.commit();
  });
}};

}  // namespace cmd_noise
}  // namespace geotex::cli
