#pragma once
//! \file mrf.h Mesh denoising with Markov random fields and explicit sharp-edge labelling (thesis
//! ch. 6, optimizers of ch. 4.3).
//!
//! Two coupled processes alternate (Sec. 6.3.4–6.3.5): the *edge process* labels every edge with
//! ε ∈ [0, 1] (how likely it lies on a sharp ridge) for fixed geometry, minimizing
//!   U_E(ε) = Σ_e (φ0 − φ_e) ε_e − w Σ_{pairs (e_ij, e_jk)} cos θ_ijk ε_ij ε_jk      Eq. (6.9–6.11), w = ½,
//! and the *vertex process* moves the vertices for fixed labels, minimizing
//!   U_V(X) = α Σ_i ‖x_i⁰ − x_i‖² + Σ_{4-cliques} (1 − ε_jk) ρ(‖n_ijk − n_jlk‖)     Eq. (6.4), (6.13),
//! with ρ(y) = y² (the quadratic potential, Eq. 6.7) or ρ(y) = y (the square-root potential).
//!
//! Units: positions enter U_V divided by the input's mean edge length, so that α = 0.1 means the
//! same on a mesh of any size; angles are in radians (Eq. 6.9).
//!
//! The face-normal variant (Sec. 6.5) runs the same edge process beside an MRF whose sites are
//! faces labelled with unit normals,
//!   U_N(n) = α_n Σ_f ‖n_f − n_f⁰‖² + Σ_e (1 − ε_e) ρ(‖n_f − n_g‖),
//! then fits the vertex positions to the normals (Sun et al. 2007's update, the thesis' [127]).

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"

namespace geotex {

//! ρ in Eq. (6.6).
enum class SmoothnessPotential {
  Quadratic,  //!< ρ(y) = y², Eq. (6.7): aggressive; edges are kept by the labels
  SquareRoot  //!< ρ(y) = y: feature preserving on its own (Diebel et al. 2006)
};

//! Which ridges the edge process may label (curvature clamping, Sec. 6.5).
enum class RidgeSign {
  All,      //!< convex and concave: φ_e = |dihedral angle|
  Convex,   //!< only convex ridges: φ_e = signed dihedral angle (valleys count as negative)
  Concave   //!< only concave valleys: φ_e = −signed dihedral angle
};

//! Optimizer of a process (ch. 4.3).
enum class MrfOptimizer {
  Metropolis,  //!< Metropolis sampler with simulated annealing (Sec. 4.3.2–4.3.3, 6.3.5)
  Icm,         //!< iterated conditional modes, every site updated from the previous configuration (4.3.1)
  Cg,          //!< vertex process only: nonlinear conjugate gradients (Polak–Ribière+) on U_V
  Lbfgs        //!< vertex process only: L-BFGS on U_V
};

//! Names: "quadratic|sqrt", "all|convex|concave", "metropolis|icm|cg|lbfgs".
const EnumNames<SmoothnessPotential>& potential_names();
const EnumNames<RidgeSign>& ridge_names();
const EnumNames<MrfOptimizer>& optimizer_names();
//! Parse a name (see the tables above). \throw InvalidInput.
SmoothnessPotential parse_potential(const std::string& name);
RidgeSign parse_ridges(const std::string& name);
MrfOptimizer parse_optimizer(const std::string& name);
std::string to_string(SmoothnessPotential p);
std::string to_string(RidgeSign r);
std::string to_string(MrfOptimizer o);

//! The edge process (Sec. 6.3.3).
struct EdgeProcessOptions {
  double phi0_deg = 40.0;           //!< ridge sharpness threshold φ0, degrees (Fig. 6.3: 40°)
  double support_weight = 0.5;      //!< weight of the neighbourhood support U_E2, Eq. (6.11)
  RidgeSign ridges = RidgeSign::All;  //!< curvature clamping (Sec. 6.5)
  MrfOptimizer optimizer = MrfOptimizer::Metropolis;  //!< Metropolis (thesis) or Icm
  //! T_E, start temperature of the edge process. Fig. 6.3 used 0.05 under a schedule the thesis does
  //! not give; 0.2 cooled by 0.95 per iteration measured clearly better here (bench/mrf.md).
  double temperature = 0.2;
  double cooling = 0.95;            //!< T_E is multiplied by this after each outer iteration
  int sweeps = 1;                   //!< sweeps over all edges per outer iteration
  //! End the annealing at T = 0: in the last outer iteration the edge sweep takes each site's
  //! conditional mode (ICM), so that the final labels are exactly 0 or 1.
  bool quench = true;
  //! Threshold annealing (not in the thesis; 0 = off): when above φ0, the threshold starts here and
  //! falls linearly to φ0 over the first half of the outer iterations, so that noise-sharp edges of
  //! the input are not frozen as ridges before the geometry has been smoothed.
  double phi0_start_deg = 0.0;
  static const OptionTable<EdgeProcessOptions>& table();
};

//! The vertex process and the alternation (Sec. 6.3.1–6.3.5).
struct MrfOptions {
  double alpha = 0.1;               //!< likelihood weight α, Eq. (6.4) (thesis: 0.1)
  SmoothnessPotential potential = SmoothnessPotential::Quadratic;  //!< ρ in Eq. (6.6)
  MrfOptimizer optimizer = MrfOptimizer::Lbfgs;  //!< vertex-process optimizer
  double temperature = 0.0;         //!< T_v, start temperature of the vertex process (Fig. 6.3: 0)
  double cooling = 0.5;             //!< T_v is multiplied by this after each outer iteration ("decays quickly")
  double step = 0.1;                //!< Metropolis: initial proposal std. dev., mean edge lengths (adapted)
  int iterations = 80;              //!< outer iterations (edge process, then vertex process)
  int vertex_sweeps = 0;            //!< per outer iteration: sweeps (Metropolis, ICM) or line searches
                                    //!< (CG, L-BFGS); 0 = the optimizer's default (5, 2, 5, 5)
  double tolerance = 1e-6;          //!< stop when labels are unchanged and U_V fell by less than this fraction
  //! After the last alternation, this many more sweeps / line searches of the vertex process: the
  //! minimum of U_V for the final labels (Eq. 6.15), where 5 per alternation only approach it.
  int final_sweeps = 100;
  EdgeProcessOptions edges;         //!< the edge process
  //! Final labelling (not in the thesis; 0 = off): after the final vertex sweeps, label the ridges
  //! once more on the denoised geometry with this threshold φ0 (ICM from ε = [φ > φ0], Eq. 6.12); the
  //! geometry is not changed. The alternation's φ0 = 40° keeps subtle ridges while the surface forms;
  //! this one reports which edges are sharp (Sec. 6.3.3: "to detect right angle ridges, a threshold
  //! corresponding to approximately 90° is appropriate"). 60° measured best (bench/mrf.md: Fandisk0.3
  //! label precision 0.79 → 0.92 at recall 0.92, geometry unchanged).
  double final_phi0_deg = 60.0;
  bool initial_labels_from_angles = true;  //!< start with ε_e = [φ_e > φ0] (Fig. 6.3), else ε = 0
  uint64_t seed = 1;                //!< random seed: same seed, same result (any thread count)
  ProgressFn progress;              //!< called after each outer iteration
  //! Presets: "thesis" (Fig. 6.3's run: Metropolis vertex and edge processes, T_E 0.05 cooled by 0.9,
  //! 20 iterations, no extras).
  static const OptionTable<MrfOptions>& table();
};

//! What one run produced.
struct MrfResult {
  MatrixX3d positions;              //!< #V by 3 denoised positions (connectivity unchanged)
  Eigen::VectorXd edge_labels;      //!< #E labels ε in [0, 1], OpenMesh edge order
  std::vector<double> vertex_energy;  //!< U_V (or U_N for the normal variant) after each outer iteration
  std::vector<double> edge_energy;    //!< U_E after each outer iteration
  std::vector<int> labelled;          //!< edges with ε > ½ after each outer iteration
  std::vector<double> seconds;        //!< wall time since the start, after each outer iteration
  int iterations = 0;               //!< outer iterations run
  bool converged = false;           //!< stopped by the tolerance
};

//! Denoise a mesh with the coupled vertex and edge processes (Sec. 6.3).
//! \throw InvalidInput for an empty mesh, non-finite coordinates or bad options.
MrfResult mrf_denoise(const Mesh& mesh, const MrfOptions& options = {});

//! The face-normal variant (Sec. 6.5).
struct MrfNormalOptions {
  double alpha = 0.1;               //!< weight α_n of ‖n_f − n_f⁰‖² (the normal field's likelihood)
  SmoothnessPotential potential = SmoothnessPotential::Quadratic;  //!< ρ on ‖n_f − n_g‖
  MrfOptimizer optimizer = MrfOptimizer::Icm;  //!< normal process: Icm (closed-form site update) or Metropolis
  double temperature = 0.0;         //!< Metropolis: start temperature of the normal process
  double cooling = 0.5;             //!< its factor per outer iteration
  double step = 0.1;                //!< Metropolis: proposal std. dev. of a normal (radians, adapted)
  int iterations = 80;              //!< outer iterations (edge process, then normal process)
  int normal_sweeps = 2;            //!< normal-process sweeps per outer iteration
  int vertex_iterations = 20;       //!< iterations of the vertex update fitting positions to normals
  int rounds = 1;                   //!< repeat (normals from the updated mesh, MRF, vertex update)
  double tolerance = 1e-6;          //!< stop a round when labels are unchanged and U_N fell by less than this
  EdgeProcessOptions edges;         //!< the edge process
  bool initial_labels_from_angles = true;  //!< start with ε_e = [φ_e > φ0]
  uint64_t seed = 1;                //!< random seed
  ProgressFn progress;              //!< called after each outer iteration
  static const OptionTable<MrfNormalOptions>& table();
};

//! Denoise with the face-normal MRF and the edge process, then fit positions to the normals.
//! \throw InvalidInput for an empty mesh, non-finite coordinates or bad options.
MrfResult mrf_normal_denoise(const Mesh& mesh, const MrfNormalOptions& options = {});

//! Sharp edges of a fixed geometry: the edge process (Eq. 6.9–6.12) by ICM from ε = [φ > φ0] until no label
//! changes (at most 50 sweeps), as MrfOptions::final_phi0_deg labels the denoised mesh.
//! \param X #V by 3 positions. \return #E labels, 0 or 1 (0 on boundary edges). \throw InvalidInput.
Eigen::VectorXd label_sharp_edges(const Mesh& mesh, const MatrixX3d& X, const EdgeProcessOptions& options = {});

//! \name Clique potentials, for tests and for anyone building their own energy.
//! A 4-clique (i, j, k, l) is the pair of faces f_ijk and f_jlk sharing the edge e_jk (Fig. 6.1).
//! \{

//! (1 − ε) ρ(‖n_ijk − n_jlk‖), Eq. (6.6), (6.13). \param grad if given, receives ∂U/∂(x_i, x_j, x_k, x_l)
//! as a 4 by 3 matrix (zero where the normal difference vanishes under the square-root potential).
double clique_smoothness(const Vec3& xi, const Vec3& xj, const Vec3& xk, const Vec3& xl, SmoothnessPotential rho,
                         double label = 0.0, Eigen::Matrix<double, 4, 3>* grad = nullptr);

//! α ‖x⁰ − x‖², Eq. (6.4). \param grad if given, receives ∂U/∂x.
double likelihood_potential(const Vec3& x0, const Vec3& x, double alpha, Vec3* grad = nullptr);

//! (φ0 − φ) ε, Eq. (6.9) (radians). \param grad if given, receives ∂U/∂ε.
double edge_sharpness_potential(double phi, double phi0, double label, double* grad = nullptr);

//! −w cos θ_ijk ε_ij ε_jk for the edges e_ij and e_jk, Eq. (6.10) weighted as in (6.11); θ_ijk is the angle
//! between the directed edges x_j − x_i and x_k − x_j. \param grad if given, receives ∂U/∂(ε_ij, ε_jk).
double edge_support_potential(const Vec3& xi, const Vec3& xj, const Vec3& xk, double label_ij, double label_jk,
                              double weight = 0.5, Eigen::Vector2d* grad = nullptr);
//! \}

//! Total energies of a configuration (for tests and reports).
//! \param X #V by 3 positions; \param X0 #V by 3 data positions; \param labels #E edge labels.
//! Positions are used as given (no scaling by the mean edge length).
double vertex_energy(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& X0, const Eigen::VectorXd& labels,
                     double alpha, SmoothnessPotential rho);
double edge_energy(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& labels,
                   const EdgeProcessOptions& options = {});

//! One sweep of a single process on a given configuration, for tests and experiments. Positions are
//! used as given (no scaling). \p sweep_index and \p seed make the random choices reproducible.
//! \return the process' energy after the sweep.
double vertex_process_sweep(const Mesh& mesh, MatrixX3d& X, const MatrixX3d& X0, const Eigen::VectorXd& labels,
                            double alpha, SmoothnessPotential rho, MrfOptimizer optimizer, double temperature = 0,
                            double step = 0.05, uint64_t seed = 1, int sweep_index = 0);
double edge_process_sweep(const Mesh& mesh, const MatrixX3d& X, Eigen::VectorXd& labels,
                          const EdgeProcessOptions& options, double temperature, uint64_t seed = 1,
                          int sweep_index = 0);

}  // namespace geotex
