#pragma once
//! \file synthesis.h Height-and-tilt texture synthesis (the step the thesis' ch. 10 closes on): grow a
//! texture over a whole target surface from an exemplar, with the exemplar's statistics of height and
//! lean, its features' sizes and spacing, and its lean turned to follow a direction field on the target;
//! then apply it.
//!
//! Method: patch-based synthesis by best-matching overlaps — image quilting (Efros and Freeman, "Image
//! quilting for texture synthesis and transfer", SIGGRAPH 2001) carried onto a surface as in lapped
//! textures (Praun, Finkelstein and Hoppe, SIGGRAPH 2000), with the local displacement (x, y tangent, z
//! along the normal: height and lean, Eq. 8.5–8.8) as the signal:
//!  1. Exemplar: a geodesic disk of the exemplar base mapped conformally onto the unit disk with its
//!     anchor direction along +u (disk_map(), transfer.h); its texture is read as displacements in the
//!     frames (+u, +v, n) (TextureSampler) and rastered once (two samples per exemplar edge at least). A unit-disk point z stands for the
//!     exemplar-plane point z R, R² the map's area scale over |z| < 0.8.
//!  2. Target: refined where it is coarser than the exemplar scaled to it (refine_region()); a smooth
//!     tangent direction field (direction_field.h) orients every patch and every local frame.
//!  3. Patches: disks of radius patch_radius × R × scale around centres chosen in a growing front (the
//!     uncovered vertex nearest to the patches so far, with seeded jitter: each new patch overlaps the
//!     ones before it), parametrized by the discrete exponential map (Schmidt, Grimm and Wyvill,
//!     "Interactive decal compositing with discrete exponential maps", SIGGRAPH 2006; single-parent
//!     Dijkstra variant), the centre's frame along the field, carried by parallel transport.
//!  4. Matching: among `candidates` random placements (translations in the exemplar disk; the rotation
//!     is the field's) the patch takes one whose displacements agree best with what is already
//!     synthesized on the overlap (Σ b |new − old|² / Σ b (|new|² + |old|²): normalised, so that where
//!     nothing matches the quietest parts of the exemplar are not preferred), at random among those within
//!     match_tolerance of the best (Efros and Freeman): the seed decides, nothing repeats verbatim.
//!  5. Seams (seams = cut, the default): the patch is pasted along a minimum cut of its overlap —
//!     graph-cut textures (Kwatra, Schödl, Essa, Turk and Bobick, "Graphcut textures: image and video
//!     synthesis using graph cuts", SIGGRAPH 2003): overlap vertices next to already written vertices
//!     outside the patch keep theirs, those next to unwritten patch vertices take the patch's, and the
//!     border is the cut of least Σ over cut edges (a, b) of |old − new|(a) + |old − new|(b) (max flow,
//!     Dinic), so features are copied whole where the two disagree. The cut is feathered over `feather`
//!     rings (both displacements are known there). Folds: the placements are tried in turn (the chosen
//!     one, then the others by cost) until one folds no more faces around the patch than there were
//!     (`fold_tries`) and crosses no more (`avoid_crossings`: self_intersecting_faces() over the written
//!     faces near the patch, against what is placed and the target); the features of a placement that
//!     still collides are dropped (`drop_collisions`: zeroed, feathered); what still folds at the end is
//!     shrunk smoothly (`unfold`, the last resort: Gaussian dips of radius `unfold_radius` × the patch
//!     radius around each folded face, until none folds). Then (`fill_holes`) where a whole feature of the
//!     exemplar has room, patches centred there (a Poisson-disk rule at its closest feature spacing), each
//!     with one of its features at the centre, kept only if it neither crosses nor folds.
//!     seams = blend: overlapping patches are averaged with weights b^p, b = (1 − |u|²/r²)² (1 at a
//!     patch's centre, 0 at its rim, p = blend_power) — uncorrelated relief averages out, and features
//!     from two patches cross where they overlap.
//!  6. The displacements (faded by the growth weight) are encoded as a height-and-tilt texture on the
//!     target (texture_from_local()) and applied.
//!
//! Units: lengths on the target are `scale` × lengths in the exemplar; displacements too (features keep
//! their proportions and their lean), times height_scale.

#include <cstdint>
#include <functional>
#include <utility>
#include <string>
#include <vector>

#include "geotex/core/progress.h"
#include "geotex/texture/texture.h"
#include "geotex/toolkit/geodesic.h"
#include "geotex/toolkit/direction_field.h"

namespace geotex {

//! How overlapping patches meet.
enum class SeamMethod { Cut, Blend };
//! "cut", "blend".
const EnumNames<SeamMethod>& seam_method_names();

struct SynthesisEstimate;

struct SynthesisOptions {
  // Exemplar
  //! Exemplar base vertex at the centre of the exemplar disk (−1: automatic — on an open base the vertex
  //! farthest from the boundary, on a closed one the vertex nearest the area centroid).
  int exemplar_center = -1;
  //! Geodesic radius of the exemplar disk in exemplar units (0: automatic — 0.95 × the centre's distance
  //! to the boundary on an open base, 0.2 × √area on a closed one; shrunk until the region is a disk).
  double exemplar_radius = 0;
  //! The exemplar's anchor: its tangent part at the exemplar centre is turned onto the target's field.
  Vec3 exemplar_direction = Vec3::UnitX();

  // Scale
  //! Target length per exemplar length (displacements too). 0: automatic, so that the exemplar disk's
  //! area is exemplar_share of the target's (textured) area.
  double scale = 0;
  //! Automatic scale: the exemplar disk's share of the target's area. 0: automatic — 0.05, or larger
  //! (at most 0.5) where the target refined to the exemplar's resolution would exceed vertex_budget.
  double exemplar_share = 0;
  double height_scale = 1.0;     //!< multiply the displacements by this, on top of the scale

  // Patches
  //! Patch radius as a share of the exemplar disk's radius R (the placements are the translations that
  //! keep the patch inside the exemplar disk, so it must be below 1).
  double patch_radius = 0.35;
  //! A patch is centred at every vertex farther than this share of the patch radius from all centres.
  double patch_spacing = 0.6;
  int candidates = 64;            //!< random placements compared per patch
  double match_tolerance = 0.1;   //!< choose among placements with cost ≤ (1 + tolerance) × the best
  int match_samples = 128;        //!< overlap vertices compared per placement (at most)
  SeamMethod seams = SeamMethod::Cut;  //!< cut (a minimum cut of each overlap) or blend (weighted mean)
  double blend_power = 8.0;       //!< seams = blend: overlap weights b^p, larger, narrower blends
  int feather = 1;                //!< seams = cut: rings on either side of a cut over which the two are mixed
  //! seams = cut: placements tried in turn (the chosen one, then the others best first) until one folds no
  //! more faces than there were around the patch (else the one that folds fewest); 1: no check.
  int fold_tries = 8;
  //! seams = cut: placements are also tested for crossings (self_intersecting_faces() on the written faces
  //! near the patch: against what is placed and the target) and tried in turn until one crosses no more
  //! faces than there were; the features of one that still crosses are dropped (drop_collisions).
  bool avoid_crossings = true;
  //! seams = cut: where the placement kept still crosses faces, zero the displacement of the colliding
  //! features (connected vertices displaced by over 5 % of the largest displacement, feathered: the whole
  //! feature, also its part outside the patch, within the patch radius plus the largest displacement of
  //! the patch's centre; a feature cut at the patch's rim leaves a wall that folds).
  bool drop_collisions = true;
  //! seams = cut: after the front, patches centred wherever a whole feature has room (no displaced vertex
  //! within 0.9 × the exemplar's closest feature spacing less its footprint radius, nor within that radius),
  //! none nearer than that spacing to another, one of the exemplar's features at the centre (a Poisson-disk
  //! fill at the exemplar's feature spacing), kept only if it neither crosses nor folds.
  bool fill_holes = true;
  //! Where the textured surface still crosses itself after encoding (beyond the base), zero the features
  //! there as drop_collisions does, unfold, and encode again (at most 4 times).
  bool repair_crossings = true;
  //! seams = cut: after unfolding, remove broken features (issue 27): a connected region displaced by over 5 %
  //! of the largest displacement whose peak is under half the lowest of the exemplar's whole features, or whose
  //! footprint is under 3/4 of their smallest (a short broken piece of a feature cut by a seam, a rim or a
  //! drop), is zeroed and feathered, before crossings are counted.
  bool remove_fragments = true;
  //! seams = cut: drop the features of a kept placement that still folds faces too (rather than leaving
  //! the folds to unfold).
  bool drop_folds = false;
  //! Shrink the displacements around faces they fold (and not the base), by 0.75 a round at the face and
  //! less away from it (a Gaussian dip), until none does.
  bool unfold = true;
  //! The unfolding dip's radius ρ (the dip reaches 2ρ) as a share of the patch radius, at least the folded
  //! face's mean edge: one fold wide (with the tentacle plate on a refined target a twentieth is under an edge,
  //! so the face's edge decides), so that the features around it keep their relief (bench/synthesis.md: with
  //! the tentacle plate on a sphere a quarter shrank 15 % of the vertices by over 1 %, a tenth 4.7 %, a
  //! twentieth 2 %; spot 5.2 % at a tenth, 2.4 % at a twentieth).
  double unfold_radius = 0.05;

  // Keep-out: where a person would not cover the target by default (each multiplies the growth weight, by
  // degree; bench/synthesis.md). The texture's feature length (its largest displacement on the target) sets
  // the scale of each.
  //! Keep texture off sharp creases: edges whose dihedral angle exceeds this (degrees), faded in from a
  //! quarter of the texture's span to the span away from them (0: no crease keep-out).
  double keep_out_crease_angle = 60;
  //! Keep texture off parts smaller than its features: where the surface within the texture's span (the
  //! smaller of its feature length and patch radius) is under a quarter of a flat disk's area (none), rising
  //! to full texture at a half (a finger or leg of radius ρ holds about 4ρ / span).
  bool keep_out_thin = true;
  //! Keep texture out of closed pits smaller than its span (an eye socket with no crease round it): where the
  //! surface round a vertex, in rings of a quarter, a half and the whole span, stands above it on every side
  //! (the lowest of 8 sectors) by at least this share of the ring's radius; faded in from a quarter of the span
  //! to the span away (0: no pit keep-out; bench/synthesis.md).
  double keep_out_pit_depth = 0.15;
  //! Keep texture off domes smaller than its span (an eyeball with no crease round it): islands closed round
  //! by a ridge whose mean curvature exceeds this over the span (or a valley below minus half of it), smaller
  //! than a disk of the span's radius, convex, standing above the surface round them (which faces their way)
  //! and alone on it (a calm surface round them, not a field of similar islands: a head's eyes, not curls of
  //! hair); faded in from a quarter of the span to the span away (0: no dome keep-out; bench/synthesis.md).
  double keep_out_dome_ridge = 1;

  // Orientation
  //! The direction field's guide (when no per-vertex guide is given): its tangent part on the target.
  Vec3 direction = Vec3::UnitX();
  DirectionFieldOptions field;

  // Control
  uint64_t seed = 1;  //!< same seed, same result
  //! Refine the target where its mean edge exceeds this × the exemplar's mean edge scaled to it (0: never).
  double refine_ratio = 1.0;
  HeatGeodesicOptions geodesic;  //!< the exemplar disk's geodesic distance
  TextureOptions texture;        //!< decoding the exemplar, encoding the result
  //! Automatic exemplar_share: the output vertex count (after refinement) it aims at.
  int vertex_budget = 100'000;
  //! Refuse (InvalidInput, before any work) when the estimated output vertex count exceeds this.
  int max_vertices = 1'000'000;
  ProgressFn progress;           //!< called as the work goes on, from refinement to encoding (not in the table)
  //! Called once, before the work, with the estimate (not in the table).
  std::function<void(const SynthesisEstimate&)> on_estimate;

  //! Table.
  static const OptionTable<SynthesisOptions>& table();
};

//! What a synthesis will cost, known before the work (the exemplar disk and the target's size).
struct SynthesisEstimate {
  double exemplar_share = 0;  //!< used (given, or automatic)
  double scale = 0;           //!< target length per exemplar length
  size_t vertices = 0;        //!< output vertices (the target after refinement), estimated
  bool refine = false;        //!< whether the target will be refined
  double seconds = 0;         //!< CPU seconds, estimated (one core; bench/synthesis.md)
};

//! Per-vertex guides on the target (each optional: leave empty).
struct SynthesisGuides {
  //! #V of the target in [0, 1]: where texture grows (0: none; displacements are faded by it as a
  //! transfer's rim is). Patch centres are only placed where the weight is ≥ 0.5.
  Eigen::VectorXd weight;
  //! #V by 3 of the target: the direction field's guide per vertex (instead of options.direction).
  MatrixX3d direction;
};

struct SynthesisResult {
  Mesh target;          //!< the target base used (refined where it was coarser): the input's vertices first
  Texture texture;      //!< on \ref target
  MatrixX3d textured;   //!< #V by 3: the textured target (the texture applied)
  MatrixX3d field;      //!< #V by 3 unit tangent directions the lean follows (the local frames' e1)
  MatrixX3d local;      //!< #V by 3 synthesized displacements in the frames (field, n × field, n)
  Eigen::VectorXd weight;  //!< #V: the growth weight used (the guide's, spread onto new vertices; else 1)
  Eigen::VectorXi owner;   //!< #V: the patch with the largest blend weight at a vertex (−1: none)
  //! #V by 3: the owner patch's exemplar displacement at the vertex, in the exemplar frame (+u, +v, n),
  //! times height_factor (what the lean direction is compared with).
  MatrixX3d copied;
  std::vector<int> centers;  //!< patch centres (vertices of \ref target)
  double scale = 1;          //!< target length per exemplar length used
  double height_factor = 1;  //!< scale × height_scale: what exemplar displacements were multiplied by
  double patch_radius = 0;   //!< patch radius on the target (target units)
  size_t added_vertices = 0; //!< vertices the refinement added
  size_t unfolded_vertices = 0;  //!< vertices whose displacement \ref SynthesisOptions::unfold shrank
  //! Collisions at placement (seams = cut): patches whose first placement folded or crossed faces and a
  //! later one did not; patches whose features were dropped; vertices zeroed by dropping.
  size_t retried_placements = 0, dropped_patches = 0, dropped_vertices = 0;
  //! Vertices zeroed after encoding, where the textured surface still crossed itself (drop_collisions).
  size_t repaired_vertices = 0;
  //! Patches placed by fill_holes (in \ref centers too).
  size_t filled_patches = 0;
  //! Broken features removed (remove_fragments) and the vertices they zeroed.
  size_t fragments_removed = 0, fragment_vertices = 0;
  //! Area share of the growth region (weight ≥ 0.5) left bare: where a whole feature would fit (no vertex displaced
  //! by over 5 % of the largest displacement within the exemplar's largest footprint radius). The exemplar's own
  //! is about 0 (the tentacle plate's: 0); 0 for an exemplar without separate features.
  double bare_share = 0;
  //! Faces turned against the base (issue 27): among the relief's faces (a corner displaced by over 5 % of the
  //! largest displacement), the area share of those whose normal points against the base's normal at the same
  //! face; and the same for the exemplar as it is read (its raster over the placements' reach, a flat base).
  //! The undersides of leaning features count in both: what exceeds the exemplar's is what synthesis turned.
  double inward_share = 0, exemplar_inward_share = 0;
  int exemplar_center = -1;  //!< the exemplar disk used (automatic or given)
  double exemplar_radius = 0;   //!< its geodesic radius (exemplar units)
  double exemplar_extent = 0;   //!< R: exemplar length per unit-disk length (the map's scale over |z| < 0.8)
  SynthesisEstimate estimate;   //!< the estimate made before the work
  //! Damage counts: faces of \ref textured crossed by an edge of a non-adjacent face
  //! (self_intersecting_faces()), the same on the refined base, and the excess (textured beyond base).
  size_t self_intersecting = 0, base_self_intersecting = 0, excess_self_intersecting = 0;
  double shrunk_share = 0;   //!< unfolded_vertices / #V: vertices whose (non-zero) displacement unfold shrank by over 1 %
  double refined_share = 0;  //!< added_vertices / #V
  //! Area shares of the target kept out (automatic keep-out weight below 0.5): in all, and by each reason.
  double kept_out_share = 0, kept_out_creases = 0, kept_out_thin = 0, kept_out_pits = 0, kept_out_domes = 0;
  std::vector<std::pair<std::string, double>> stage_seconds;  //!< wall seconds per stage, in order
  std::vector<std::string> warnings;
};

//! Estimate the cost of synthesize_texture() with the same arguments (an exemplar disk is made; the
//! target is not refined). \throw as synthesize_texture().
SynthesisEstimate estimate_synthesis(const Mesh& exemplar_base, const Texture& exemplar, const Mesh& target,
                                     const SynthesisOptions& options = {}, const SynthesisGuides& guides = {});

//! Synthesise a texture like \p exemplar (over \p exemplar_base) on the whole of \p target and apply it
//! (see the file comment). \throw InvalidInput for bad options, a texture that does not match its base,
//! no exemplar disk, or guides of the wrong size.
SynthesisResult synthesize_texture(const Mesh& exemplar_base, const Texture& exemplar, const Mesh& target,
                                   const SynthesisOptions& options = {}, const SynthesisGuides& guides = {});

// ---------------------------------------------------------------------------------------------
// Measures

//! Features of a height field: points whose height is ≥ \p threshold and the largest within Euclidean
//! distance \p radius (greedy, highest first). \return their indices, highest first.
std::vector<int> height_features(const MatrixX3d& points, const Eigen::VectorXd& h, double radius, double threshold);

//! How a synthesis compares with its exemplar (bench/synthesis.md says how each is measured).
struct SynthesisQuality {
  //! Pseudo-height (Eq. 8.5) histograms, area-weighted, the exemplar's times height_factor: total
  //! variation distance in [0, 1] on 40 bins spanning both, and the Wasserstein-1 distance over the
  //! exemplar's mean |h|.
  double histogram_tv = 0, histogram_w1 = 0;
  double exemplar_rms = 0, target_rms = 0;  //!< area-weighted rms heights (the exemplar's × height_factor)
  //! Features (height_features(): radius = twice the exemplar's correlation length (first zero of the
  //! autocorrelation), threshold = mean + std of
  //! its heights) and their mean nearest-neighbour distance (target units; the exemplar's over the
  //! features nearer to a neighbour than to the disk's rim).
  size_t exemplar_features = 0, target_features = 0;
  double exemplar_spacing = 0, target_spacing = 0;
  double spacing_change = 0;  //!< target_spacing / exemplar_spacing − 1
  //! Lean direction: over covered vertices leaning more than 5° with |h| ≥ 10 % of the largest, the
  //! angle between the lean's direction measured from the field and the exemplar's measured from its
  //! anchor at the point the vertex's owner patch copied; mean weighted by |d| sin(lean), degrees.
  double lean_angle_error_deg = 0;
  //! Height steps |h_i − h_j| over edges between patches (owners differ) and within patches, over the
  //! largest exemplar |h| × height_factor: 99th percentile and maximum.
  double seam_step99 = 0, seam_step_max = 0, within_step99 = 0, within_step_max = 0;
  double coverage = 0;  //!< area share of the target (weight > 0) that received a displacement
  size_t folded = 0;    //!< folded faces of the textured target (folded_faces()) beyond the base's own
};

//! Measure \p result against the exemplar it was synthesised from (same options).
SynthesisQuality synthesis_quality(const Mesh& exemplar_base, const Texture& exemplar, const SynthesisResult& result,
                                   const SynthesisOptions& options = {});

}  // namespace geotex
