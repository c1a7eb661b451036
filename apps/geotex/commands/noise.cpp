// geotex noise IN -o OUT: seeded Gaussian (or impulsive) noise in mean-edge-length units.

#include "cli.h"
#include "geotex/tools/noise.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string input, output;
  NoiseOptions opt;
  bool ascii = false;
};

void run(const Args& a) {
  check_output(a.input, a.output);
  Mesh mesh = load_mesh(a.input);
  set_positions(mesh, add_noise(mesh, a.opt));
  save_mesh(mesh, a.output, !a.ascii);
}

Registrar reg{30, "noise", "Add seeded noise (sigma in units of the mean edge length)", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output mesh")->required();
  app.add_option("--sigma", a->opt.sigma, "standard deviation in mean edge lengths")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_flag("--normal", a->opt.along_normal, "displace along vertex normals (default: random directions)");
  app.add_option("--impulsive", a->opt.impulsive_fraction, "fraction of vertices hit (impulsive noise); 0 = all")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--seed", a->opt.seed, "random seed")->capture_default_str();
  app.add_flag("--ascii", a->ascii, "ascii PLY/STL output");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
