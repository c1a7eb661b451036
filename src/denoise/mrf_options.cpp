// Names and option tables of the MRF denoisers (thesis ch. 6): the one description of every option,
// from which the CLI flags, the Python keyword arguments and the reports are made.

#include "geotex/denoise/mrf.h"

namespace geotex {

const EnumNames<SmoothnessPotential>& potential_names() {
  static const EnumNames<SmoothnessPotential> n = {{"quadratic", SmoothnessPotential::Quadratic},
                                                   {"sqrt", SmoothnessPotential::SquareRoot}};
  return n;
}
const EnumNames<RidgeSign>& ridge_names() {
  static const EnumNames<RidgeSign> n = {{"all", RidgeSign::All}, {"convex", RidgeSign::Convex}, {"concave", RidgeSign::Concave}};
  return n;
}
const EnumNames<MrfOptimizer>& optimizer_names() {
  static const EnumNames<MrfOptimizer> n = {{"metropolis", MrfOptimizer::Metropolis}, {"icm", MrfOptimizer::Icm},
                                            {"cg", MrfOptimizer::Cg}, {"lbfgs", MrfOptimizer::Lbfgs}};
  return n;
}
SmoothnessPotential parse_potential(const std::string& s) { return parse_enum(potential_names(), s, "smoothness potential"); }
RidgeSign parse_ridges(const std::string& s) { return parse_enum(ridge_names(), s, "ridge selection"); }
MrfOptimizer parse_optimizer(const std::string& s) { return parse_enum(optimizer_names(), s, "optimizer"); }
std::string to_string(SmoothnessPotential p) { return enum_name(potential_names(), p); }
std::string to_string(RidgeSign r) { return enum_name(ridge_names(), r); }
std::string to_string(MrfOptimizer o) { return enum_name(optimizer_names(), o); }

const OptionTable<EdgeProcessOptions>& EdgeProcessOptions::table() {
  using O = EdgeProcessOptions;
  static const auto t = OptionTable<O>()
      .add("phi0", &O::phi0_deg, "ridge sharpness threshold phi0, degrees", angle_deg(), "Eq. (6.9)")
      .add("support", &O::support_weight, "weight of the edge neighbourhood support", non_negative(), "Eq. (6.11)")
      .choice("ridges", &O::ridges, ridge_names(), "edges that may be labelled: all, convex or concave (curvature clamping)",
              "Sec. 6.5")
      .choice("edge_optimizer", &O::optimizer, {{"metropolis", MrfOptimizer::Metropolis}, {"icm", MrfOptimizer::Icm}},
              "edge process: metropolis (annealed, the thesis) or icm", "Sec. 6.3.5")
      .add("te", &O::temperature, "edge-process start temperature T_E", non_negative(), "Sec. 6.3.5")
      .add("te_cooling", &O::cooling, "T_E factor per outer iteration (annealing schedule)", {0, 1, true, false})
      .add("edge_sweeps", &O::sweeps, "edge-process sweeps per outer iteration", at_least(1))
      .add("quench", &O::quench, "last outer iteration: the edge process at T = 0 (labels exactly 0 or 1)")
      .add("phi0_start", &O::phi0_start_deg,
           "anneal the threshold from this angle (degrees) down to phi0 over the first half of the iterations; 0 = off",
           angle_deg());
  return t;
}

const OptionTable<MrfOptions>& MrfOptions::table() {
  using O = MrfOptions;
  static const auto t = OptionTable<O>()
      .add("alpha", &O::alpha, "likelihood weight alpha (positions in mean edge lengths)", non_negative(), "Eq. (6.4)")
      .choice("potential", &O::potential, potential_names(), "smoothness potential rho: quadratic or sqrt (rho(y) = y)",
              "Eq. (6.6-6.7)")
      .choice("optimizer", &O::optimizer, optimizer_names(), "vertex-process optimizer", "Sec. 4.3")
      .add("tv", &O::temperature, "vertex-process start temperature T_v (Metropolis only)", non_negative(), "Sec. 6.3.5")
      .add("tv_cooling", &O::cooling, "T_v factor per outer iteration", {0, 1, true, false})
      .add("step", &O::step, "Metropolis proposal std. dev., mean edge lengths (adapted)", positive())
      .add("iterations", &O::iterations, "outer iterations (edge process, then vertex process)", non_negative(), "Sec. 6.3.4")
      .add("sweeps", &O::vertex_sweeps,
           "vertex sweeps (metropolis, icm) or line searches (cg, lbfgs) per outer iteration; 0 = 5, 2, 5, 5",
           non_negative())
      .add("tolerance", &O::tolerance, "stop when labels are stable and U_V fell by less than this fraction", non_negative())
      .add("final_sweeps", &O::final_sweeps, "vertex sweeps or line searches after the last alternation", non_negative())
      .add("final_phi0", &O::final_phi0_deg,
           "label the sharp edges once more on the denoised geometry with this threshold (degrees); 0 = off",
           angle_deg())
      .add("initial_labels", &O::initial_labels_from_angles,
           "start the edge process from the edges whose dihedral angle exceeds phi0 (else from no labels)", {}, "Fig. 6.3")
      .add("seed", &O::seed, "random seed: same seed, same result on any number of threads")
      .nest(&O::edges, EdgeProcessOptions::table())
      .preset("thesis", "the thesis' run (Fig. 6.3): Metropolis on both processes, T_E 0.05 cooled by 0.9, 20 iterations",
              [](O& o) {
                o.optimizer = MrfOptimizer::Metropolis;
                o.iterations = 20;
                o.final_sweeps = 0;
                o.final_phi0_deg = 0;
                o.edges.temperature = 0.05;
                o.edges.cooling = 0.9;
                o.edges.quench = false;
                o.edges.phi0_start_deg = 0;
              });
  return t;
}

const OptionTable<MrfNormalOptions>& MrfNormalOptions::table() {
  using O = MrfNormalOptions;
  static const auto t = OptionTable<O>()
      .add("alpha", &O::alpha, "weight alpha_n of the normal field's likelihood", non_negative(), "Sec. 6.5")
      .choice("potential", &O::potential, potential_names(), "smoothness potential rho on normal differences",
              "Eq. (6.6-6.7)")
      .choice("optimizer", &O::optimizer, {{"icm", MrfOptimizer::Icm}, {"metropolis", MrfOptimizer::Metropolis}},
              "normal-process optimizer: icm (closed-form site update) or metropolis", "Sec. 4.3")
      .add("tv", &O::temperature, "normal-process start temperature (Metropolis only)", non_negative())
      .add("tv_cooling", &O::cooling, "its factor per outer iteration", {0, 1, true, false})
      .add("step", &O::step, "Metropolis proposal std. dev. of a normal, radians (adapted)", positive())
      .add("iterations", &O::iterations, "outer iterations (edge process, then normal process)", non_negative())
      .add("normal_sweeps", &O::normal_sweeps, "normal-process sweeps per outer iteration", at_least(1))
      .add("vertex_iterations", &O::vertex_iterations, "iterations fitting the vertices to the normals", non_negative())
      .add("rounds", &O::rounds, "rounds of (normal MRF, vertex fit)", at_least(1))
      .add("tolerance", &O::tolerance, "stop a round when labels are stable and U_N fell by less than this fraction",
           non_negative())
      .add("initial_labels", &O::initial_labels_from_angles,
           "start the edge process from the edges whose dihedral angle exceeds phi0 (else from no labels)")
      .add("seed", &O::seed, "random seed")
      .nest(&O::edges, EdgeProcessOptions::table())
      .preset("thesis", "the thesis' settings: Metropolis edge process, T_E 0.05 cooled by 0.9, 20 iterations", [](O& o) {
        o.iterations = 20;
        o.edges.temperature = 0.05;
        o.edges.cooling = 0.9;
        o.edges.quench = false;
        o.edges.phi0_start_deg = 0;
      });
  return t;
}

}  // namespace geotex
