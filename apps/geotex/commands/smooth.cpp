// geotex smooth IN -o OUT: explicit or implicit Laplacian smoothing (thesis Sec. 5.1.3).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/toolkit/smoothing.h"
#include "option_flags.h"

namespace geotex::cli {
namespace cmd_smooth {  // named, not anonymous: a unity build compiles several commands in one unit

Registrar reg{40, "smooth", "Laplacian smoothing: explicit (Eq. 5.12) or implicit (Eq. 5.14), umbrella or cotangent", [](CLI::App& app) {
  auto io = std::make_shared<MeshIo>(app);
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("smooth", SmoothingOptions::table());
  app.callback([io, flags] {
    SmoothingOptions o = flags->resolve<SmoothingOptions>("smooth");
    Outputs out({io->input}, {{io->output, "-o"}});
    Mesh mesh = load_mesh(io->input);
    o.progress = progress_printer("smooth");
    const auto t0 = std::chrono::steady_clock::now();
    set_positions(mesh, smooth(mesh, o));
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    info(fmt::format("smoothed {} vertices: {} {} step(s) of lambda {} in {:.2f} s ({})", mesh.n_vertices(), o.steps,
                     o.implicit ? "implicit" : "explicit", o.lambda, sec, SpdSolver::backend()));
    save_mesh(mesh, io->output, !io->ascii);
    out.commit();
  });
}};

}  // namespace cmd_smooth
}  // namespace geotex::cli
