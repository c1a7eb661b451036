#pragma once
//! \file resize.h Feature-aware resizing and deformation (thesis ch. 9): a spatial deformation (space
//! map or an edited mesh) is applied while the features, given by per-vertex weights f_i ∈ [0, 1]
//! (feature_map.h), keep their shape and size.
//!
//! Three formulations, and a separable warp for box scales. The default, ResizeMethod::Auto, runs
//! AxisSimilarity on a box scale and Similarity on any other deformation (bend, twist, arc, deformed copy);
//! resolved_resize_method() says which, and ResizeResult::method reports it.
//!  - ResizeMethod::Similarity: for continuous weights f_i ∈ [0, 1] (the importance map of
//!    feature_map.h). Every edge is pulled towards T_ij (x_i − x_j), T_i = s_i R_i the nearest
//!    similarity to the space map's local linear part (polar rotation; s_i its smallest singular value
//!    in the tangent plane, so a (2, 1, 1) stretch keeps sizes and a uniform scale scales), with
//!    stiffness f_ij², and weakly (β) towards the mapped edge c_i − c_j; every vertex is held with
//!    weight w_S (1 − f_i) to the plain-stretched surface along its normal (it may slide along it), and
//!    the vertices at the bounding box's faces to the map along their axis. Important regions thus get
//!    near-similarities and the unimportant ones absorb the stretch, with no rim: the weights are
//!    smooth. Local-global rounds refit the rotations to the solution (as-rigid-as-possible) and
//!    re-project onto the stretched surface (by default the surface term is split off by alternation,
//!    see SimilaritySolver, so that x, y and z are solved apart); faces that turn over against the
//!    plain map are relaxed to it (with a few rings around them) and the system solved again; a last
//!    per-axis scale of a few parts in 10⁴ puts the box exactly where the map does.
//!  - ResizeMethod::Thesis, Eq. (9.2–9.3): feature vertices keep their Laplacian coordinates turned
//!    by T_i (a similarity fitted by SVD between the original and the space-mapped 1-rings), every
//!    vertex is pulled to its space-mapped position c_i with weight w p_i, p_i = 1 − f_i. The preset
//!    "thesis" solves Eq. (9.3) as written: W multiplies the rows of the least-squares system, so the
//!    energy weighs the terms by f_i² and (w p_i)².
//!  - ResizeMethod::Sliding (for binary maps; what Sec. 9.5 and ch. 10 propose): background vertices are held
//!    only to the deformed base surface, along its normal, so they can slide along it and make room;
//!    the mesh boundary and the extreme vertices of the bounding box are pinned to the space map, and
//!    weak edge terms spread the stretch over the background. Feature edges keep their original
//!    vectors turned by one rotation per feature, fitted on its foot ring (it turns with the tangent
//!    plane of its base); an elongated feature (a ridge) is turned by a rotation field instead, the
//!    base's rotations around it interpolated harmonically over it, so that it bends with a bent or
//!    twisted base rather than standing straight on it. (Laplacian coordinates alone cannot do this:
//!    an in-plane affine map of a flat region leaves them unchanged, so a feature whose rim is
//!    stretched stretches along.) Three things keep rims free of rings and creases: the background's
//!    edges pass from the features' rotation to the map's own local linear map over a band around
//!    them (\ref ResizeOptions::transition), feature weights taper off over two rings outside them,
//!    and the background slides along the deformed base, not along the features' deformed surface.
//!    A feature at the box's extreme (an ear at the tip) is pushed, with its surroundings, until its
//!    outermost vertex lands where the map puts it, so the box is scaled as asked. The stretch collects
//!    in the background between the features, which keep their shape and size.
//!  - ResizeMethod::Axis (box scales only, `--scale`): x' = g_x(x), y' = g_y(y), z' = g_z(z), each g_a
//!    increasing, chosen so that important faces scale as uniformly as the box allows (axis_warp.h,
//!    Kraevoy et al. 2008). No face can turn over and the box is exact; the stretch collects in the
//!    slabs of the box that hold little of importance. A bend, twist, arc or deformed copy is refused
//!    (InvalidInput): a separable warp cannot follow it. ResizeMethod::AxisSimilarity runs Similarity
//!    with the warp's output in place of the plain map, its edges following the warp's with
//!    AxisWarpOptions::follow_weight times (1 − f_ij)^p (AxisWarpOptions::follow_falloff: important
//!    regions follow their similarity, not the warp), and relaxes faces turned against the warp or the
//!    plain stretch.

#include <functional>
#include <string>
#include <vector>

#include "geotex/core/geometry.h"
#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/resize/feature_file.h"
#include "geotex/core/progress.h"
#include "geotex/resize/axis_warp.h"
#include "geotex/resize/feature_map.h"
#include "geotex/resize/measure.h"
#include "geotex/resize/protrusion_placement.h"
#include "geotex/resize/untangle.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/space_maps.h"

namespace geotex {

//! Anisotropic scaling about \p centre: x ↦ centre + diag(s) (x − centre).
SpaceMap scale_map(const Vec3& s, const Vec3& centre = Vec3::Zero());
//! Shear-type bend along x: z ↦ z + κ (x − x0)² / 2 (verticals stay vertical, so protrusions
//! tilt against the bent base under the plain map).
SpaceMap bend_map(double kappa, double x0 = 0.0);
//! Twist about the x axis: rotation by τ (x − x0) radians about the line through (x0, 0, 0) along x.
SpaceMap twist_map(double tau, double x0 = 0.0);
//! Bend the x axis into a circular arc of radius \p radius in the xz-plane, curving towards +z: the
//! line z = z0 through x = x0 keeps its length, θ = (x − x0) / radius,
//! (x, y, z) ↦ (x0 + (radius − (z − z0)) sin θ, y, z0 + radius − (radius − (z − z0)) cos θ).
SpaceMap arc_map(double radius, double x0 = 0.0, double z0 = 0.0);

//! A space deformation built from parts, applied in this order: scale, twist, bend, arc (each about
//! the bounding box's centre). The default is the identity.
struct SpaceMapOptions {
  Vec3 scale = Vec3::Ones();  //!< anisotropic scale factors about the box centre
  double twist = 0;           //!< radians per unit length about the x axis through the centre
  double bend = 0;            //!< shear bend along x: z += K (x − x_c)² / 2
  double arc_radius = 0;      //!< bend the x axis into an arc of this radius (0: none)
  bool identity() const { return scale == Vec3::Ones() && twist == 0 && bend == 0 && arc_radius == 0; }
  static const OptionTable<SpaceMapOptions>& table();
};

//! The composed space map for a model with bounding box \p box. \throw InvalidInput for bad options.
SpaceMap space_map(const SpaceMapOptions& options, const BoundingBox& box);

enum class ResizeMethod {
  Sliding,  //!< binary features rigid, background slides along the deformed surface; frame pinned
  Thesis,   //!< Eq. (9.2–9.3): weighted Laplacian least squares with p_i = 1 − f_i
  Similarity,  //!< continuous weights: near-similarities where important
  //! An axis-aligned separable warp (axis_warp.h, after Kraevoy et al. 2008); box scales only.
  Axis,
  //! The axis warp, then Similarity with the warp in place of the plain map; box scales only.
  AxisSimilarity,
  //! AxisSimilarity on a box scale, Similarity on any other deformation (default): axis-similarity was better
  //! than similarity on 28 of 29 ×2 x/y/z runs and turned no face (bench/resize.md, eleventh session).
  Auto
};
//! "auto", "similarity", "sliding", "thesis", "axis", "axis-similarity".
const EnumNames<ResizeMethod>& resize_method_names();

//! How the similarity method minimizes its energy.
enum class SimilaritySolver {
  //! The surface term w (1 − f_i) (n_iᵀ(x_i − q_i))² as min over p_i on the plane of w (1 − f_i) |x_i − p_i|²,
  //! by alternation: x, y and z apart (three scalar #V systems, refactored only when faces are relaxed).
  Split,
  Coupled  //!< one 3#V system with the surface term in it (refactored whenever the planes move)
};
//! "split", "coupled".
const EnumNames<SimilaritySolver>& similarity_solver_names();

struct ResizeOptions {
  ResizeMethod method = ResizeMethod::Auto;
  //! w of Eq. (9.2): weight of the position terms against the feature terms.
  double position_weight = 1.0;
  //! Features keep their size (T_i a rotation, default), or scale with the map (T_i a similarity,
  //! "rotation and scale" in Sec. 9.4).
  bool keep_feature_size = true;
  //! Thesis: weigh the energy by the squares f_i², (w p_i)² of the weights, as the least-squares system
  //! W [L; I] X = W [D^t; C] of Eq. (9.3) does; false: Eq. (9.2)'s f_i and w p_i.
  bool square_weights = false;
  //! Sliding and Similarity: weight of the background's edge terms (its edges follow the passage from the features'
  //! rotations to the space map, see \ref transition) against the features' 1; small, so that the
  //! background gives way before the features do.
  double background_smoothness = 0.002;
  //! Sliding: width of the band around the features over which the background's stretch passes from
  //! the features' (none) to the space map's, in units of R = √(area / 4π). 0: the background follows
  //! the space map up to the features' rims (the stretch piles up there).
  double transition = 0.3;
  //! Sliding and Similarity: weight of pinning the frame (mesh boundary, and the bounding box's extreme vertices along
  //! their axis) to the space map.
  double frame_weight = 10.0;
  //! Sliding: a feature within this many mean edge lengths of a bounding-box face reaches it (and is
  //! pushed so that the box is scaled as asked), for axes along which the mesh extends at least a
  //! quarter of its largest extent. Similarity: vertices this close to a box face are pinned to the map
  //! along its axis.
  double frame_band = 1.5;
  //! Sliding: re-project onto the deformed surface and re-solve this many extra times (curved bases).
  int refinements = 1;
  //! Sliding: feature weights fall off linearly over this many vertex rings outside each feature (f
  //! (k+1−d)/(k+1) at ring d), so that its rim passes from rigid to held-to-the-base over a band
  //! rather than in one crease.
  int taper = 2;
  //! Sliding: elongated features (principal extents e1 > 2 e2, a ridge) bend with their base (a
  //! rotation field interpolated from their foot); compact ones, and all with false, turn as rigid
  //! pieces (one rotation per feature, fitted on its foot ring).
  bool bend_features = true;
  //! Similarity: weight w_S of holding vertex i with weight w_S (1 − f_i) to the plainly stretched surface
  //! along its normal, against the edges' (f_ij² for the similarities, β for the map). Small: the
  //! unimportant surface slides and changes shape enough to take the stretch (on cow, spot, cheburashka
  //! and fandisk ×2 the detail ratio to the plain stretch went 0.71 → 0.20 average from w_S 1 to 0.01).
  double surface_weight = 0.01;
  //! Similarity: local-global rounds after the first solve (rotations and scales refitted; the surface
  //! re-projected in the first and the middle one).
  int iterations = 6;
  //! Similarity: the scale s_i of an important vertex is refitted in each round to what fits the
  //! solution best, within the map's smallest and largest stretch there (as similar as possible: the
  //! detail may grow uniformly rather than stretch); false: fixed by keep_feature_size.
  bool adapt_scale = true;
  //! Similarity: the split solver (default; stanford-bunny ×2 y: 4–5 s CPU against 9–10 s coupled, detail
  //! ratio 0.57 against 0.59; bench/resize.md) or the coupled one.
  SimilaritySolver solver = SimilaritySolver::Split;
  //! Similarity, split solver: alternation steps per local-global round.
  int split_steps = 2;
  //! Similarity: rounds that relax faces turned over against the plain map (and \ref flip_rings rings
  //! around them, two more each round) to the map, and solve again.
  int flip_rounds = 8;
  int flip_rings = 2;
  LaplacianType laplacian = LaplacianType::Umbrella;  //!< Eq. (9.1) uses the umbrella operator
  //! Similarity and AxisSimilarity: protrusions (tentacles, ears, horns: protrusion_placement.h) are put back
  //! as rigid pieces where their foot went, at their size (as keep_feature_size), the seam blended; the rest of
  //! the model is stretched per axis to hold them in the asked box, but only where that room can be made: at
  //! most half of the rest important (importance ≥ 1/2) and the per-axis factors settling; elsewhere the
  //! method's own result stands. The tentacle stick ×2 keeps every tentacle's length within 0.6% and lean within
  //! 1.3° on x, y and z (off: up to 162% / 22°); cheburashka, 92% of whose head and body is important, is left
  //! as the method makes it (bench/resize.md, twelfth session). false: per-vertex similarities only.
  bool rigid_protrusions = true;
  //! AxisSimilarity: where the result crosses itself beyond the input's own (parts moved by different similarities
  //! run into each other: the teapot's lid against its body), blend it back towards the axis warp over a smooth bump
  //! until it does not, finishing towards the plain stretch what the warp crosses itself (untangle.h). The ×2 x/y/z
  //! runs of the shared models crossed up to 149 faces beyond their own, none after (bench/resize.md, issue 25
  //! thirteenth session). Every method counts the faces (ResizeResult::untangle); Similarity is not repaired: blended
  //! towards the plain stretch, the teapot ×2 x went from detail ratio 0.36 to 0.95 and the cow ×2 y from 0.19 to 0.83.
  //! false: counted only (research).
  bool untangle = true;
  //! Similarity, Axis and AxisSimilarity (and Auto): solve on the mesh with its coincident vertices welded
  //! (weld_coincident(): unwelded patches, as the teapot's, are one surface), the copies of a point contact (the
  //! teapot's handle on its body) held together by stiff springs in the similarity stage. false: the mesh as stored, each patch and part solved apart (its seams
  //! and contacts may open; ResizeResult::welded_vertices 0). Thesis and Sliding never weld.
  bool weld = true;
  //! Axis and AxisSimilarity: the separable warp's grid and weights (options axis_cells, axis_smoothness, …).
  AxisWarpOptions axis;
  ProgressFn progress;
  static const OptionTable<ResizeOptions>& table();
};

//! Feature-aware deformation. \param mesh the original, \param deformed #V by 3 positions after the
//! spatial deformation (c_i), \param features #V weights f_i in [0, 1]. \return #V by 3 positions.
//! \throw InvalidInput on size mismatch, weights outside [0, 1] or non-finite input; SolverError.
//! \param untangled when given, the faces the result crosses against the input's own (untangle.h).
//! Similarity, Axis and AxisSimilarity (and Auto) solve on the mesh with its coincident vertices welded
//! (weld_coincident(): unwelded patches, as the teapot's, are one surface for the solve; a weight is the largest of
//! its copies'); every input vertex gets its welded vertex's position, so coincident vertices stay coincident. A
//! point welded per fan (a part touching the body at a point) is held together by stiff springs in the similarity
//! stage (Weld::ties): its copies end within a small fraction of an edge length.
MatrixX3d feature_aware_resize(const Mesh& mesh, const MatrixX3d& deformed, const Eigen::VectorXd& features,
                               const ResizeOptions& options = {}, UntangleReport* untangled = nullptr);

//! The method feature_aware_resize() runs for \p options on the deformation X ↦ C (#V by 3 each): options.method,
//! or for Auto, AxisSimilarity when C is a box scale of X (box_scale_of(), every stretch positive) and Similarity
//! otherwise.
ResizeMethod resolved_resize_method(const ResizeOptions& options, const MatrixX3d& X, const MatrixX3d& C);

//! Convenience: apply \p map to every vertex and call the function above.
MatrixX3d feature_aware_resize(const Mesh& mesh, const SpaceMap& map, const Eigen::VectorXd& features,
                               const ResizeOptions& options = {});

//! Everything one resize takes: the space map, the feature map (or how a feature file is read) and the
//! solver; the options of `geotex resize` and geotex.resize(), one flag or keyword per field. The
//! preset "thesis" is ResizeOptions' own.
struct ResizeRunOptions {
  SpaceMapOptions map;
  FeatureMapOptions features;
  FeatureFileOptions feature_file;  //!< used by the front ends when they read a feature file
  ResizeOptions resize;
  ProgressFn progress;  //!< the whole run: the feature map, then the solve
  static const OptionTable<ResizeRunOptions>& table();
};

struct ResizeResult {
  MatrixX3d V;                 //!< #V by 3 resized positions
  MatrixX3d mapped;            //!< #V by 3 positions c_i under the plain deformation
  Eigen::VectorXd features;    //!< #V weights f_i used
  //! The detector that made the map (Height or Adf; for Auto, the one chosen); None when the weights
  //! were given or the method is none.
  FeatureMapMethod detector = FeatureMapMethod::None;
  FeatureSummary summary;      //!< share of the surface marked, and the warning when it is implausible
  //! The method run (for Auto, the one chosen: resolved_resize_method()).
  ResizeMethod method = ResizeMethod::Similarity;
  //! Faces the result crosses, against the input's own, before and after ResizeOptions::untangle.
  UntangleReport untangle;
  //! Input vertices welded onto a coincident one for the map and the solve (weld.h; the methods that solve for
  //! positions, not thesis or sliding), and the coincident groups left apart or welded per fan because welding them
  //! whole would make the mesh worse (weld_coincident()). The fields above are per input vertex all the same.
  int welded_vertices = 0;
  int weld_refused_groups = 0;
};

//! One feature-aware resize as the front ends run it (for the methods that solve for positions, the feature map and
//! the solve run on the mesh with its coincident vertices welded, weld.h, as feature_aware_resize() does): the deformation is options.map (about the
//! bounding box's centre) or, when given, \p deformed (#V by 3, e.g. an edited copy; options.map must
//! then be the identity); the features are \p features (#V weights in [0, 1]) when given, else
//! feature_map() with options.features (the one definition of "auto").
//! \throw InvalidInput for no deformation or two, sizes that do not match, bad options.
ResizeResult resize_mesh(const Mesh& mesh, const ResizeRunOptions& options, const MatrixX3d* deformed = nullptr,
                         const Eigen::VectorXd* features = nullptr);

}  // namespace geotex
