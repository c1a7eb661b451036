#pragma once
//! \file auto_denoise.h The default denoiser: one call that reads the input (noise level, creased or
//! smooth) and runs the combination of the thesis' methods measured best on synthetic noise over the
//! shared clean models (bench/denoise.md).
//!
//! The pipeline (auto_denoise()):
//!  1. the noise level, estimate_noise(), and per region (AutoDenoiseResult::noise_map): a mesh read nearly
//!     noise-free but for some regions is denoised at their level, each region measured against its own (the
//!     creased budget, the change kept: the rest left as it is);
//!  2. a mild surfel pass (ch. 7, IRLS weights; thresholds from 2.5× the median angle between neighbouring
//!     initial surfels down to 20°, 4 sweeps): the smooth (organic) reading;
//!  3. the sharp surfel pass from the initial surfels (thresholds from 0.85× that median down to 10°,
//!     30 sweeps, cluster moves; what surfel_denoise() runs by default): the creased (CAD-like) reading;
//!  4. positions fitted to each reading's face normals (Sun et al. 2007 with tangential relaxation);
//!  5. the reading per region, not per mesh (issue 24): each vertex takes the fit whose residual against
//!     the input along the normals, over its neighbourhood, is the smaller, with a threshold set by its
//!     part's look (creased-looking parts lean to the sharp reading), and the sharp fit wherever a learned
//!     model (reading_model.h) is sure it is the better one (AutoDenoiseOptions::reading); a soft per-face map
//!     (AutoDenoiseResult::creased) blends the two in transitions; --creased / --no-creased force one;
//!     the creased reading is refused where the sharp fit moves an organic-looking part by more than the noise
//!     (AutoDenoiseOptions::creased_budget, AutoDenoiseResult::refused); a CAD-looking part whose sharp-fit residual
//!     runs one way across it (a scanner's stripes) is read creased throughout (AutoDenoiseOptions::stripe_coherence),
//!     and so is any part whose residual runs one way more strongly (stripe_coherence_organic: short bands fool the look),
//!     and any part that both fits move far beyond the noise estimated (low_frequency_residual: low-frequency noise);
//!  5b. the smooth reading's relief per region: a light fit (1 mild sweep, 3 updates) keeps fine relief and
//!     some noise; each vertex keeps it in the Wiener proportion of its local energy over the local noise
//!     energy (AutoDenoiseOptions::relief_floor, AutoDenoiseResult::relief), so eyes, nostrils and carved
//!     detail keep their shape where a plain sphere is still smoothed fully;
//!  5c. the smooth reading smoothed as strongly as the sharp pass where that is safe: each vertex read smooth
//!     takes the sharp fit where it departs from the mild one by less than the noise and its normals vary
//!     less around the vertices (a dense sphere or torus at moderate noise: the mild pass leaves noise the sharp
//!     pass removes; AutoDenoiseOptions::strong_floor, AutoDenoiseResult::strong);
//!  6a. the smooth reading's change given back where it is spatially coherent beyond the noise
//!     (coherent_change.h): removed noise is white from vertex to vertex, a coarse mesh's own facets smoothed
//!     away are not (AutoDenoiseOptions::coherence_weight, AutoDenoiseResult::change_kept);
//!  6. the change kept in proportion to the noise: x_in + s (x_fit − x_in), s = σ⁴ / (σ⁴ + σ0⁴) with σ the
//!     RMS normal noise (impulses included) of the vertex's region, so that a noiseless mesh is returned as it is;
//!  7. faces turned over against their target normals are untangled (their vertices moved to the mean of
//!     their neighbours until none is left);
//!  8. labels: the edge process (Eq. 6.12) on the result, φ0 = 60° in creased regions and 75° in smooth
//!     ones (only folds that stand out: no invented creases on organic shapes).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"

namespace geotex {

//! How noisy a mesh is, from leave-one-out local fits: at sampled interior vertices, a cubic height
//! function over the tangent plane of the two-ring (without the vertex) predicts the vertex; the
//! residuals, scaled by their expected spread, give the standard deviation of the displacement along the
//! surface normal. Only the half of the vertices whose two-ring the cubic fits best count (creases and
//! detail fit badly; in a least-squares fit the residuals are independent of the prediction, so this
//! choice does not bias the vertex's own residual), and their mean square without outliers is used,
//! which holds whatever the shape of the noise's distribution.
//!
//! The estimate assumes isotropic noise (random directions, `geotex noise`'s default) when it converts the
//! normal component to a full displacement and corrects the mean edge length for the lengthening noise
//! causes; it cannot tell noise along the normals from isotropic noise (for that, normal_sigma is the sigma).
struct NoiseEstimate {
  double normal_sigma = 0;  //!< std. dev. of the displacement along the normal, in (clean) mean edge lengths
  double sigma = 0;         //!< the same as isotropic noise in random directions: √3 × normal_sigma
  //! The RMS normal displacement including the outliers (impulsive noise: the few vertices it moved, which
  //! normal_sigma leaves out), mean edge lengths.
  double rms_normal_sigma = 0;
  double outliers = 0;      //!< fraction of the residuals left out of normal_sigma as outliers
  double mean_edge = 0;     //!< the mean edge length of the (noisy) mesh, absolute
  //! The mean edge length before the noise, the unit of the estimate: noise lengthens edges, by
  //! E|e_noisy|² = E|e|² + 2 s² for isotropic noise of variance s² per vertex.
  double clean_edge = 0;
  int samples = 0;          //!< vertices used
  //! The growth of the fit's residual from the two-ring cubic to a three-ring quartic (about 1 for noise;
  //! above it, a coarse model's facets the cubic cannot follow)
  double misfit_growth = 1;
  //! The share of the residual read as noise by that growth (1: all of it), applied to the estimate above
  double noise_share = 1;
};

//! Estimate the noise of \p mesh from at most \p max_samples vertices (evenly strided).
//! \throw InvalidInput for an empty mesh or one without interior vertices of large enough two-rings.
NoiseEstimate estimate_noise(const Mesh& mesh, int max_samples = 20000);

//! How each region's reading (creased or smooth) is decided (step 5).
enum class ReadingRule {
  //! rule_reading(), and sharp wherever the learned model (reading_model.h) gives p > 0.9 (default)
  Combined,
  Rule,     //!< the previous release's hand-made threshold alone (rule_reading())
  Learned,  //!< the learned model alone (sharp where p > 1/2)
};
//! "combined", "rule", "learned".
const EnumNames<ReadingRule>& reading_rule_names();

//! Options of auto_denoise(). Unset ("auto") values are derived from the input.
struct AutoDenoiseOptions {
  //! The noise level, as `geotex noise --sigma` (isotropic, mean edge lengths); auto: estimate_noise().
  std::optional<double> sigma;
  //! Whether the surface has sharp creases (CAD-like) or is smooth (organic) everywhere; auto: read per
  //! region from the input.
  std::optional<bool> creased;
  int mild_iterations = 4;      //!< sweeps of the mild surfel pass (every input)
  int sharp_iterations = 30;    //!< threshold steps of the sharp surfel pass (creased inputs)
  int fit_iterations = 20;      //!< vertex updates fitting the positions to the normals (Sun et al. 2007)
  //! The smooth reading's relief, per region (step 5b): a light fit (this many mild sweeps, then
  //! light_fit_iterations updates) keeps fine relief, and each vertex keeps it where the local energy of the
  //! light fit's departure from the mild one stands above relief_floor × the local noise energy.
  int light_iterations = 1;
  int light_fit_iterations = 3;  //!< vertex updates of the light fit
  //! The noise floor of step 5b in units of the local noise energy: 0 keeps the light fit everywhere, a
  //! large value the mild fit everywhere (the previous release's smooth reading).
  double relief_floor = 0.13;
  //! Step 5: the creased reading is refused on organic-looking parts (look above 0.6) where the sharp fit moves
  //! the input along the normals by more than creased_budget × the normal noise variance (the median of the
  //! squared moves over a vertex's closed 1-ring, averaged over 2 rings): it flattens shape there, not noise.
  //! 0 never refuses (the previous release).
  double creased_budget = 1.0;
  //! Step 5, depth noise: a scanner's noise runs along its viewing axis a, so its variance along a normal is
  //! σ² (n·a)², above the mesh's estimate where the surface faces the scanner; there the creased budget is measured
  //! against the noise along the normal (the mild fit's move fitted as nᵀ Σ n), where Σ's smallest eigenvalue is
  //! below depth_anisotropy × its largest (white noise on the shared models 0.16-0.91, depth noise on a cylinder
  //! below 0.01; bench/denoise.md, fourteenth session). 0 never (the previous release).
  double depth_anisotropy = 0.1;
  //! Step 5, scanner stripes: a CAD-looking part (look below 0.6) is read creased throughout where the gradient
  //! of the sharp fit's residual along the normals points one way across it (the coherence of its structure
  //! tensor, (λ1 − λ2) / (λ1 + λ2), above stripe_coherence): bands of a scanner, not relief (white noise 0-0.22,
  //! stripes 0.44-0.80 on fandisk and the cube; bench/denoise.md). 1 never (the previous release).
  double stripe_coherence = 0.3;
  //! Step 5, scanner stripes on a part whatever its look: bands 4 edges apart make a CAD part look organic (fandisk
  //! 0.72, the cube 1.38), yet its residual's coherence stays high (0.56, 0.73); an organic part's residual is
  //! mostly the shape the sharp fit flattens, which runs no one way (0.03-0.32 under white and striped noise on
  //! the shared models). Above stripe_coherence_organic any part is read creased throughout where the bands stand
  //! above the noise (a smooth cylinder's shape alone reaches 0.44 under white noise, with a residual at the noise
  //! level), the creased budget not applied (bench/denoise.md, thirteenth session). 1 never (the previous release).
  double stripe_coherence_organic = 0.4;
  //! Step 5, scanner stripes whose direction differs face to face: the bands are one function of a·x for one
  //! world axis a, fitted in 3D from the residual's gradients and refined to where one sinusoid (period 3-32 edges)
  //! explains most of the sharp fit's residual. A CAD-looking part is read creased throughout where that share is
  //! above stripe_share (white noise at most 0.12, stripes 0.19-0.83; the cube under stripes 16 edges apart 0.60,
  //! woody under oblique stripes 0.60); a part of any look where it is, if its coherence is above
  //! stripe_coherence_organic (in place of the bands' energy) or the share above 1.5 × stripe_share (a cylinder
  //! under oblique stripes; organic models under stripes reach 0.33; bench/denoise.md, fifteenth session). 1 never
  //! (the previous release).
  double stripe_share = 0.3;
  //! Step 5, low-frequency scanner noise: a smooth field a few edges across, which the noise estimate follows (σ̂
  //! a tenth of σ) and the mild fit keeps as relief. A part is read creased throughout where the median of the sharp
  //! fit's residual (5 rings) is above low_frequency_residual × the normal noise variance (the part's own estimate,
  //! on a mesh of several parts) and the mild fit's is within a factor e^0.5 of it (not shape that the sharp fit
  //! alone flattens): 30-87 under such a field over 4-6 edges, at most 12.5 elsewhere within that factor (white noise
  //! at most 7); the creased budget is not applied there (bench/denoise.md, fourteenth session). 0 never (the
  //! previous release).
  double low_frequency_residual = 20;
  //! Step 5, flat regions: a region the sharp fit makes one plane (its faces joined where their normals differ by
  //! less than 10°, 150+ vertices) is read creased throughout where the input's root-mean-square distance from its
  //! least-squares plane is at most plane_misfit × the region's normal noise (noise_map) and a quadric explains no
  //! more than noise would: a cylinder's caps under white or depth noise 0.9-1.2, organic regions of that size 1.5+.
  //! Only where the noise runs along one axis (depth_anisotropy's test): under white noise an organic region whose
  //! curvature is below the noise passes too (bench/denoise.md, sixteenth session). 0 never (the previous release).
  double plane_misfit = 1.35;
  //! Step 5c: a vertex read smooth takes the sharp fit where the local energy of its departure from the
  //! mild fit stays below strong_floor × the local noise energy (in Wiener proportion) and the sharp fit's
  //! normals vary less around it: 0 never (the previous release), large values wherever it is smoother.
  double strong_floor = 0.02;
  //! Step 5c on a plain part: a part whose median energy of the sharp fit's departure from the mild fit is below
  //! plain_departure × the local noise energy (wholly below 0.6 × it; the mild fit's low-frequency wobble on pure
  //! noise is about 0.01, organic relief 0.07-0.7) has no relief to keep, and takes the sharp fit wherever the
  //! normal noise is well above its curvature per edge, whatever strong_floor's share and the roughness test say
  //! (dense primitives at high noise, where these fail at scattered vertices). 0 never (the previous release).
  double plain_departure = 0.018;
  //! Step 6, noise that differs region to region (mixed_levels.h): where the spread of the noise map (noise_map
  //! averaged over three more rings; its 90 % over its 10 % quantile) is above region_spread and holds over twenty
  //! rings (not the specks of impulses), each region keeps the share of the change of its own level. 0 never (the
  //! default: white noise reads at most 2.7, regions of different noise 3-1000, but low-frequency and depth noise
  //! 4-24 and impulses 2-1000; 4 gains on half-noisy meshes' noisy halves, not on all their quiet ones;
  //! bench/denoise.md, sixteenth session).
  double region_spread = 0;
  //! Normal noise (mean edge lengths) at which half of the change is kept: inputs much less noisy are
  //! returned (nearly) as they are.
  double keep_below = 0.02;
  //! Step 6a, the change given back where it is coherent (coherent_change.h): the part of the change along
  //! the normals that is spatially coherent beyond the noise (a coarse mesh's own facets, relief) is given
  //! back in Wiener proportion with this weight κ in the smooth reading; 0 keeps every change (the previous
  //! release).
  double coherence_weight = 0.3;
  //! Label edges whose dihedral angle after denoising exceeds this (degrees, Eq. 6.9's φ0 of a final edge
  //! process); auto: 60° on creased surfaces, 75° on smooth ones.
  std::optional<double> label_angle_deg;
  ReadingRule reading = ReadingRule::Combined;  //!< how each region's reading is decided (step 5)
  ProgressFn progress;          //!< optional progress callback
  static const OptionTable<AutoDenoiseOptions>& table();
};

struct AutoDenoiseResult {
  MatrixX3d positions;                 //!< #V by 3: the input's connectivity
  Eigen::VectorXd edge_labels;         //!< #E labels, 0 or 1 (1: a crease), OpenMesh edge order
  NoiseEstimate noise;                 //!< the noise estimate
  //! #V: the normal noise of each vertex's region (mean edge lengths, as NoiseEstimate::normal_sigma), read as
  //! estimate_noise() reads the mesh over the vertex's nearest samples (about three rings); the given level
  //! (sigma / √3) everywhere when the noise was given.
  Eigen::VectorXd noise_map;
  AutoDenoiseOptions resolved;         //!< the options with every automatic value set
  std::vector<std::string> choices;    //!< what was chosen and why, one short line each
  //! faces left turned over against their target normals (normally 0); not counted: those the input itself
  //! turns away from them where Gaussian noise could not have (a coarse model's facets: the targets' error)
  int turned_over = 0;
  //! #F: how each face was read, 1 creased (CAD-like: the sharp pass's normals), 0 smooth (organic: the
  //! mild pass's), in between a blend (transitions); constant when AutoDenoiseOptions::creased is given.
  Eigen::VectorXd creased;
  double creased_share = 0;            //!< the share of the surface area read creased (creased >= 0.5)
  //! #F: where the creased reading was refused because the sharp fit moved the input beyond the noise (the share
  //! of the face's vertices; AutoDenoiseOptions::creased_budget).
  Eigen::VectorXd refused;
  double refused_share = 0;            //!< the share of the surface area refused the creased reading (refused >= 0.5)
  //! #F: how much of the light fit's relief each face keeps in the smooth reading, 0 (plain: the mild fit)
  //! to 1 (relief well above the noise: the light fit); see AutoDenoiseOptions::relief_floor.
  Eigen::VectorXd relief;
  double relief_share = 0;             //!< the area-weighted mean of relief over the faces read smooth
  //! #F: how much each face read smooth takes of the sharp fit's stronger smoothing (step 5c), 0 (the mild
  //! fit) to 1 (the sharp fit: plain, smoothly curved, noisy); see AutoDenoiseOptions::strong_floor.
  Eigen::VectorXd strong;
  double strong_share = 0;             //!< the area-weighted mean of strong over the faces read smooth
  //! #F: the share of the change kept by step 6a (AutoDenoiseOptions::coherence_weight), 1 where the change
  //! is white like noise, towards 0 where it is coherent (a coarse mesh's facets smoothed away).
  Eigen::VectorXd change_kept;
  double change_kept_share = 1;        //!< the area-weighted mean of change_kept
  std::vector<std::pair<std::string, double>> seconds;  //!< wall time of each stage

};

//! Denoise \p mesh with the default pipeline (see the file's comment).
//! \throw InvalidInput for an invalid mesh, InvalidOption for options out of range.
AutoDenoiseResult auto_denoise(const Mesh& mesh, const AutoDenoiseOptions& options = {});

struct ReadingSamples;
//! The training samples of the learned reading (reading_model.h) from one noisy mesh and its truth \p clean
//! (#V by 3, the same connectivity): both readings fitted as auto_denoise() does (AutoDenoiseOptions::creased
//! ignored), the features of every vertex, and which fit's faces around it are nearer the truth's normals.
//! \throw InvalidInput when \p clean does not match, or the mesh is too small or noiseless (no readings fitted).
ReadingSamples reading_samples(const Mesh& noisy, const MatrixX3d& clean, const AutoDenoiseOptions& options = {});

}  // namespace geotex
