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

namespace {

// The edge process as the thesis runs it (Sec. 6.3.3, 6.3.5, Fig. 6.3).
void apply_thesis(EdgeProcessOptions& e) {
  e.phi0_deg = 40;                         // Fig. 6.3: "sharpness threshold phi0 = 40°"
  e.support_weight = 0.5;                  // Sec. 6.3.3: "weighting support energy with 1/2"
  e.ridges = RidgeSign::All;               // curvature clamping is a variant (Sec. 6.5, Fig. 6.5)
  e.optimizer = MrfOptimizer::Metropolis;  // Sec. 6.3.5: "the Metropolis sampler with simulated annealing"
  e.temperature = 0.05;                    // Fig. 6.3: "edge process temperature T_E = 0.05"
  e.cooling = 0.9;                         // not given by the thesis: annealing needs a schedule
  e.sweeps = 1;                            // not given
  e.quench = false;                        // no extras: the labels stay samples of the annealed process
  e.phi0_start_deg = 0;
}

// Sec. 6.3.1–6.3.5 and Fig. 6.3: the vertex process and its alternation with the edge process.
void apply_thesis(MrfOptions& o) {
  o.alpha = 0.1;                                  // Sec. 6.3.1: "alpha = 0.1 ... used in all final experiments"
  o.potential = SmoothnessPotential::Quadratic;   // Eq. (6.7), (6.13)
  o.optimizer = MrfOptimizer::Metropolis;         // Sec. 6.3.5
  o.temperature = 0;                              // Fig. 6.3: "vertex process temperature T_v = 0"
  o.cooling = 0.5;                                // (irrelevant at T_v = 0)
  o.step = 0.1;                                   // not given: the proposal's start size (adapted)
  o.iterations = 20;                              // not given
  o.vertex_sweeps = 5;                            // not given
  o.tolerance = 0;                                // no early stop: a fixed number of iterations
  o.final_sweeps = 0;                             // no extras
  o.final_phi0_deg = 0;
  o.initial_labels_from_angles = true;            // Fig. 6.3: "initially labelled based only on ... the dihedral angle"
  apply_thesis(o.edges);
}

// Sec. 6.5: faces as sites, normals as labels, the same edge process, then the vertex update of [127].
void apply_thesis(MrfNormalOptions& o) {
  o.alpha = 0.1;                                  // as the vertex process (the thesis gives no other value)
  o.potential = SmoothnessPotential::Quadratic;
  o.optimizer = MrfOptimizer::Metropolis;         // Sec. 6.3.5: the Metropolis sampler for every process
  o.temperature = 0;                              // as T_v: "quickly decays towards zero"
  o.cooling = 0.5;
  o.step = 0.1;                                   // not given (radians, adapted)
  o.iterations = 20;                              // not given
  o.normal_sweeps = 5;                            // not given (as the vertex process)
  o.vertex_iterations = 20;                       // Sun et al. 2007's vertex update; the count is not given
  o.rounds = 1;                                   // "the smooth normal field, which is then used for reconstructing"
  o.tolerance = 0;
  o.initial_labels_from_angles = true;
  apply_thesis(o.edges);
}

}  // namespace

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
      .add("edge_sweeps", &O::sweeps, "edge-process sweeps per outer iteration", between(1, 100))
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
      .add("iterations", &O::iterations, "outer iterations (edge process, then vertex process)", between(0, 10000), "Sec. 6.3.4")
      .add("sweeps", &O::vertex_sweeps,
           "vertex sweeps (metropolis, icm) or line searches (cg, lbfgs) per outer iteration; 0 = 5, 2, 5, 5",
           between(0, 100))
      .add("tolerance", &O::tolerance, "stop when labels are stable and U_V fell by less than this fraction", non_negative())
      .add("final_sweeps", &O::final_sweeps, "vertex sweeps or line searches after the last alternation", between(0, 10000))
      .add("final_phi0", &O::final_phi0_deg,
           "label the sharp edges once more on the denoised geometry with this threshold (degrees); 0 = off",
           angle_deg())
      .add("initial_labels", &O::initial_labels_from_angles,
           "start the edge process from the edges whose dihedral angle exceeds phi0 (else from no labels)", {}, "Fig. 6.3")
      .add("seed", &O::seed, "random seed: same seed, same result on any number of threads")
      .nest(&O::edges, EdgeProcessOptions::table())
      .preset("thesis",
              "the thesis' run (Sec. 6.3, Fig. 6.3): Metropolis on both processes, alpha 0.1, phi0 40, T_v 0, T_E 0.05 "
              "(cooled by 0.9 over 20 iterations: the schedule is not given), quadratic potential, no extras",
              [](O& o) { apply_thesis(o); });
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
      .add("iterations", &O::iterations, "outer iterations (edge process, then normal process)", between(0, 10000))
      .add("normal_sweeps", &O::normal_sweeps, "normal-process sweeps per outer iteration", between(1, 100))
      .add("vertex_iterations", &O::vertex_iterations, "iterations fitting the vertices to the normals", between(0, 1000))
      .add("rounds", &O::rounds, "rounds of (normal MRF, vertex fit)", between(1, 100))
      .add("tolerance", &O::tolerance, "stop a round when labels are stable and U_N fell by less than this fraction",
           non_negative())
      .add("initial_labels", &O::initial_labels_from_angles,
           "start the edge process from the edges whose dihedral angle exceeds phi0 (else from no labels)")
      .add("seed", &O::seed, "random seed")
      .nest(&O::edges, EdgeProcessOptions::table())
      .preset("thesis",
              "the thesis' face-normal variant (Sec. 6.5): Metropolis on normals and labels, the edge process of "
              "Fig. 6.3, one round of the vertex update of Sun et al. 2007, no extras",
              [](O& o) { apply_thesis(o); });
  return t;
}

}  // namespace geotex
