#pragma once
//! \file texture.h Height-and-tilt geometric texture (thesis ch. 8): a pseudo-height per vertex and a
//! tilt per edge (a discrete 1-form) over a base mesh, with the lean angle per vertex beside it (see
//! TiltEncoding). Extract, reconstruct, edit, animate, store and re-apply to a deformed base here;
//! the base shape is in base_shape.h, transfer between surfaces in transfer.h (both included).
//!
//! Conventions: the texture lives on the base mesh's vertices (height, lean: #V) and edges (tilt, #E,
//! in OpenMesh edge order, oriented as edges(mesh)). Normals are the base's vertex normals
//! (TextureOptions::normals), recomputed from whatever base the texture is applied to.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "geotex/core/geometry.h"
#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"
#include "geotex/texture/base_shape.h"
#include "geotex/toolkit/one_form.h"

namespace geotex {

// ---------------------------------------------------------------------------------------------
// Representation (Sec. 8.3.2–8.3.3)

//! How the size of the tilt (the lean α_i of d̂_i from ±n_i, sin α_i = ‖t_i‖) and its direction are
//! stored and decoded.
//!
//! The tilt 1-form c (Eq. 8.2) is the flux of the tangential displacement direction across the edges
//! (c_ij = (d̂_i × n_i)·e_ij = d̂_i·(n_i × e_ij)). Under a smooth map of the base with tangent-plane
//! Jacobian J, decoding it (Eq. 5.79, 8.8) turns the tangential part of d̂ into J d̂ / det J: its
//! direction is pushed forward with the surface, stretch included (a lean at 45° to a ×2 stretch turns
//! by 18°), and its length is divided by the area scale, so scaling the base by s divides sin α by s.
//! Lean and LeanPushforward differ only in decoding on a deformed base (extraction is the same).
enum class TiltEncoding {
  //! Texture::lean holds α_i and the direction turns with the base's tangent frame, as a vector
  //! displacement stored in a frame carried by the surface does (default): the direction is decoded on
  //! the rest base (Texture::rest) and turned by the rotation part R_i of the polar decomposition
  //! J_i = R_i S_i of the tangent Jacobian between the rest and the deformed one-ring. Height and lean
  //! are kept exactly under any deformation, the direction turns only with the surface's rotation.
  Lean,
  //! Texture::lean holds α_i; the direction is J d̂ from the 1-form decoded on the deformed base (it
  //! turns with the stretch: the default before issue 26).
  LeanPushforward,
  //! The thesis (Eq. 8.6–8.8): sin α_i = ‖(P c)_i‖, Texture::lean is left empty.
  OneForm,
};
//! "lean", "lean-pushforward", "one-form" (also "thesis").
const EnumNames<TiltEncoding>& tilt_encoding_names();

//! texture = ({h_i}, {c_ij}) (Eq. 8.7), with the lean per vertex (TiltEncoding::Lean).
struct Texture {
  Eigen::VectorXd height;  //!< #V pseudo-heights h_i = sign(d_i·n_i) ‖d_i‖ (Eq. 8.5), sign never 0
  Eigen::VectorXd tilt;    //!< #E tilt 1-form coefficients c_ij of t_i = d̂_i × n_i (Eq. 8.6)
  //! #V lean angles α_i ∈ [0, π/2] in radians, the angle of d̂_i from sign(h_i) n_i (Eq. 8.8's α), or
  //! empty: then sin α_i = ‖(P c)_i‖ as in the thesis (TiltEncoding::OneForm, older files).
  Eigen::VectorXd lean;
  //! #V by 3: the base positions the tilt was encoded over (the rest pose; set by extraction and the
  //! edits when the lean is stored), or empty: the base the texture is applied to. TiltEncoding::Lean
  //! decodes the direction here and turns it with the base's rotation from here to the applied base.
  MatrixX3d rest;
};
//! How the tilt 1-form is fitted (Eq. 8.2). Both minimise the same least-squares objective (Eq. 5.81).
enum class TiltSolver {
  //! CGLS from the averaging estimate (Eq. 5.80), stopped once the reconstruction it gives is within
  //! TextureOptions::fit_tolerance of the target; falls back to Direct when it stalls or runs out of
  //! iterations. No factorization: ~10× faster at 10^5–10^6 vertices (bench/texture.md).
  Iterative,
  Direct,  //!< sparse Cholesky of the #E × #E normal equations: the exact minimiser
};

//! "iterative", "direct".
const EnumNames<TiltSolver>& tilt_solver_names();

struct TextureOptions {
  NormalWeighting normals = NormalWeighting::Angle;  //!< base vertex normals n_i
  //! Where the lean's size is stored: per vertex (default; kept under scaling, bending, twisting) or
  //! in the 1-form as in the thesis (divided by the base's area scale when it is deformed); and whether
  //! its direction turns with the base's rotation (default) or with its full Jacobian.
  TiltEncoding encoding = TiltEncoding::Lean;
  //! Fit only the tilt's components in the tangent planes (OneFormFitOptions::tangential). The tilt
  //! is tangent (Eq. 8.6) and decoding keeps only the tangent part of P c (Eq. 8.8), so the thesis'
  //! full fit (false) also spends its least squares on the normal part of P c, which nothing reads: on
  //! a scan whose tilt the 1-form cannot hold exactly it leaves a larger decoded error, and its CGLS
  //! converges ~10× slower (bench/texture.md).
  bool tangential_fit = true;
  //! Keep |c_ij| ≤ ‖e_ij‖ (Sec. 8.5). Off by default: on the spiky shapes the pinned coefficients
  //! raise the round-trip error from ~1e-6 to several mean edge lengths (texture_test, bench/texture.md).
  bool bound_tilt = false;
  double regularization = 1e-8;  //!< see OneFormFitOptions::regularization
  //! Weight each vertex's tilt equation by (|h_i| / max|h|)^p + 1e-4: the position error of a
  //! reconstructed vertex is |h_i| times its direction error, so tall vertices matter most. p = 2 for
  //! the full fit; p = 1 for the tangential one, whose weights only steer CGLS (fewest iterations).
  bool height_weighted = true;
  //! Tilt fit solver. The bound |c_ij| ≤ ‖e_ij‖ (bound_tilt) always uses Direct.
  TiltSolver solver = TiltSolver::Iterative;
  //! Iterative: stop when every vertex's reconstruction (Eq. 8.8, with the fitted tilt) is within this
  //! many mean edge lengths of the target's (4× below the 1e-3 round-trip target of the tests).
  double fit_tolerance = 2.5e-4;
  int max_iterations = 500;  //!< iterative: CGLS iterations before falling back to Direct
  //! Iterative: fall back to Direct when the error shrank by less than 10 % over this many iterations,
  //! or when its rate over them puts the tolerance beyond max_iterations (on scans whose tilt the
  //! 1-form cannot hold exactly, the tolerance is out of reach).
  int stall_iterations = 100;
  //! Table; preset "thesis": one-form encoding, full fit (Eq. 5.81), |c_ij| ≤ ‖e_ij‖ (Sec. 8.5), direct.
  static const OptionTable<TextureOptions>& table();
};

//! What the last tilt fit of a TextureCodec did.
struct TiltFitReport {
  bool iterative = false;  //!< the iterative fit met fit_tolerance (false: the direct solve was used)
  int iterations = 0;      //!< CGLS iterations run (also when it fell back)
  double error = 0;        //!< the iterative fit's last max reconstruction error / mean edge length
};

//! Encoder/decoder of textures over one base mesh: the 1-form fit is analysed and factored once and
//! reused by extraction and by every edit or animation frame.
class TextureCodec {
 public:
  //! \throw InvalidInput for an empty base or non-finite coordinates.
  explicit TextureCodec(const Mesh& base, const TextureOptions& options = {});

  //! Extract the texture of \p textured (#V by 3, same connectivity as the base; Eq. 8.4–8.7).
  Texture extract(const MatrixX3d& textured);
  //! Reconstruct the textured surface (Sec. 8.3.3, Eq. 8.8). \return #V by 3 positions.
  MatrixX3d apply(const Texture& texture) const;
  //! The texture of per-vertex displacements \p D (#V by 3) from the base: extract(base + D).
  Texture from_displacements(const MatrixX3d& D) { return extract(X_ + D); }
  //! The displacements the texture gives: apply(texture) − base. \return #V by 3.
  MatrixX3d displacements(const Texture& texture) const { return apply(texture) - X_; }
  //! A texture from per-vertex unit displacement directions \p D (#V by 3) and the sizes |h_i| of
  //! \p height (the heights' signs follow D·n_i, Eq. 8.5); what the edits below produce.
  Texture from_directions(const MatrixX3d& D, const Eigen::VectorXd& height);

  //! Tilt vectors at vertices (Eq. 5.79), made tangent and clamped to length ≤ 1. \return #V by 3.
  MatrixX3d tilt_vectors(const Eigen::VectorXd& tilt) const;
  //! Encode tilt vectors at vertices as a 1-form (Eq. 8.2), weighted by \p heights when
  //! TextureOptions::height_weighted (pass an empty vector for an unweighted fit). \p lean (#V, or
  //! empty for the thesis' decoding) is how the result will be decoded: the iterative fit stops once
  //! that decoding is within tolerance. \return #E.
  Eigen::VectorXd encode_tilt(const MatrixX3d& tilt_vectors, const Eigen::VectorXd& heights = {},
                              const Eigen::VectorXd& lean = {});
  //! Unit displacement directions d̂_i = cos α n_i + n_i × t_i with sin α = ‖t_i‖, cos α = sign(h_i)
  //! √(1 − ‖t_i‖²) (Eq. 8.8; the rotation is about t_i — DESIGN.md on Sec. 8.3.3). With a lean
  //! (TiltEncoding::Lean and Texture::lean given) α is the lean and only the direction of t_i is used:
  //! d̂_i = sign(h_i) cos α_i n_i + sin α_i (n_i × t_i) / ‖t_i‖; with TiltEncoding::Lean and a
  //! Texture::rest other than this base, t_i is decoded on the rest base and (n_i × t_i)/‖t_i‖ turned
  //! by the rotation part of the polar decomposition of the one-ring's tangent Jacobian. \return #V by 3.
  MatrixX3d directions(const Texture& texture) const;

  const Mesh& base() const { return base_; }
  const TextureOptions& options() const { return options_; }
  const MatrixX3d& normals() const { return N_; }
  //! What the last extract() / encode_tilt() / edit did to fit the tilt.
  const TiltFitReport& last_fit() const { return last_fit_; }

 private:
  Mesh base_;
  MatrixX3d X_, N_;
  TextureOptions options_;
  OneFormFitter fitter_;
  double mean_edge_ = 0;
  TiltFitReport last_fit_;
};

//! One-shot: TextureCodec(base, options).extract(textured).
Texture extract_texture(const Mesh& base, const MatrixX3d& textured, const TextureOptions& options = {});
//! One-shot: TextureCodec(base, options).apply(texture). Apply to a deformed or rescaled base (same
//! connectivity) to re-apply the texture with its elements' size and shape kept (Sec. 8.4.2).
MatrixX3d apply_texture(const Mesh& base, const Texture& texture, const TextureOptions& options = {});

//! The same texture with the tilt (and lean) dropped: a plain height field along the normals.
Texture height_field_only(const Texture& texture);

//! Re-applying a texture (`geotex texture apply`, geotex.texture_apply()).
struct TextureApplyOptions {
  double height_scale = 1.0;  //!< multiply every height by this
  bool height_only = false;   //!< drop the tilt (and lean): a plain height field along the normals
  //! How the tilt is decoded on the (deformed) base: the lean's direction turned with the base's
  //! rotation (lean, default), with its Jacobian (lean-pushforward), or the thesis' 1-form (one-form).
  TiltEncoding encoding = TiltEncoding::Lean;
  //! Table (no presets: a texture extracted with the thesis' preset has no lean, and is decoded as the
  //! thesis does whatever the encoding says).
  static const OptionTable<TextureApplyOptions>& table();
};

//! apply_texture() of the texture with its heights scaled and, with height_only, its tilt dropped.
//! \return #V by 3. \throw InvalidInput for bad options or a texture that does not match \p base.
MatrixX3d apply_texture(const Mesh& base, const Texture& texture, const TextureApplyOptions& options);

// ---------------------------------------------------------------------------------------------
// Extraction from a textured mesh alone (`geotex texture extract`, geotex.texture_extract())

struct TextureExtractOptions {
  //! The automatic base (when no base is given). A step count (steps > 0) asks for the thesis'
  //! smoothing (BaseMethod::Smoothing) whatever the method says.
  BaseShapeOptions base;
  TextureOptions texture;  //!< the tilt fit
  //! A given base with the textured mesh's connectivity is used vertex for vertex; with this set, the
  //! textured vertices are projected onto it along its Phong normals, as onto a base of any connectivity.
  bool project_onto_base = false;
  //! Table: the base's options, the texture's, project_onto_base; preset "thesis": both thesis presets.
  static const OptionTable<TextureExtractOptions>& table();
};

//! Where the base of an extraction came from.
enum class BaseSource {
  Given,      //!< the given base, vertex for vertex (same connectivity: the correspondence)
  Projected,  //!< the textured vertices projected onto the given base along its Phong normals (Sec. 5.2)
  Automatic,  //!< base_shape() of the textured mesh (Sec. 8.3.1)
};

struct TextureExtraction {
  Mesh base;        //!< the base used: the textured mesh's connectivity and vertex order
  Texture texture;  //!< over \ref base
  BaseSource source = BaseSource::Automatic;
  BaseShape shape;  //!< Automatic: what base_shape() found (passes, stopped, projected, weights)
  size_t missed = 0;  //!< Projected: textured vertices without an inside solution (the closest point taken)
  double median_off_normal_deg = 0;  //!< median angle of the displacements from the base normals
  TiltFitReport fit;                 //!< how the tilt was fitted
  double max_error = 0;  //!< largest distance of a reconstructed vertex from its textured one, in mean edges
  double height_only_error = 0;  //!< the same for the height field alone (what the tilt adds)
  //! The base's area over the textured surface's: what share of the surface the base keeps (an automatic
  //! base that keeps less than kBaseAreaWarning read part of the shape as texture, or the texture is large).
  double base_area_ratio = 1;
  std::vector<std::string> warnings;  //!< one line each (an automatic base that removed much of the surface)
};

//! An automatic base keeping less of the surface's area than this is warned about (issue 26).
constexpr double kBaseAreaWarning = 0.85;

//! The texture of \p textured over \p base, or over the automatic base when \p base is null
//! (Sec. 8.3.1–8.3.2, Eq. 8.4–8.7), and how well it reconstructs \p textured.
//! \throw InvalidInput for bad options or meshes; SolverError if a solve fails.
TextureExtraction texture_extraction(const Mesh& textured, const Mesh* base,
                                     const TextureExtractOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Editing and animation (Sec. 8.4.1, Fig. 8.7). Angles in degrees; a direction is any 3D vector,
// projected onto each vertex's tangent plane.

//! Set tilt: every displacement leans by \p angle_deg from the normal towards \p direction.
Texture set_tilt(TextureCodec& codec, const Texture& texture, const Vec3& direction, double angle_deg);

//! Wrap (bend): each displacement is turned further towards \p direction by angle_deg × |h_i| / max|h|,
//! so spikes bend more towards their tips.
Texture wrap(TextureCodec& codec, const Texture& texture, const Vec3& direction, double angle_deg);

//! Wiggle / wave: a travelling sinusoid in the tilt: each displacement is turned towards \p direction
//! by amplitude_deg × sin(2π (x_i·d̂ / wavelength − phase)) × |h_i| / max|h|, x_i the base position.
//! Animate with phase = frame / frames.
Texture wiggle(TextureCodec& codec, const Texture& texture, const Vec3& direction, double amplitude_deg,
               double wavelength, double phase);

//! One edit of a whole texture (Sec. 8.4.1).
enum class TextureEditKind {
  SetTilt,      //!< set_tilt()
  Wrap,         //!< wrap()
  Wiggle,       //!< wiggle()
  ScaleHeight,  //!< scale_height()
};
//! "set-tilt", "wrap", "wiggle", "scale-height".
const EnumNames<TextureEditKind>& texture_edit_names();

struct TextureEditOptions {
  TextureEditKind op = TextureEditKind::SetTilt;
  Vec3 direction = Vec3::UnitX();  //!< lean direction (projected onto each tangent plane)
  double angle_deg = 30;           //!< set-tilt lean, wrap bend at the highest point, wiggle amplitude
  double wavelength = 0;           //!< wiggle: along the direction; 0 = a quarter of the box diagonal
  double phase = 0;                //!< wiggle: in wavelengths
  double factor = 1;               //!< scale-height: the factor
  TextureOptions texture;          //!< re-encoding the edited texture
  //! Table; preset "thesis": the thesis' encoding and fit (TextureOptions' preset).
  static const OptionTable<TextureEditOptions>& table();
};

//! The edited texture, on the same base. \throw InvalidInput for bad options or a texture that does
//! not match \p base.
Texture edit_texture(const Mesh& base, const Texture& texture, const TextureEditOptions& options);

//! An edit in motion (Fig. 8.7).
enum class AnimationKind {
  Wiggle,  //!< a travelling wave: wiggle() with phase = frame / frames
  Sway,    //!< wrap() by angle × sin(2π frame / frames): the texture sways back and forth
  Grow,    //!< heights × ½ (1 − cos(2π frame / frames)): the texture grows and shrinks
};
//! "wiggle", "wrap" (also "sway"), "grow".
const EnumNames<AnimationKind>& animation_kind_names();

struct AnimationOptions {
  AnimationKind kind = AnimationKind::Wiggle;
  int frames = 24;                    //!< frames in one period
  Vec3 direction = Vec3::UnitX();     //!< lean / wave direction (projected onto each tangent plane)
  double angle_deg = 30;              //!< wave amplitude or sway angle at the highest point
  double wavelength = 0;              //!< wiggle: along the direction; 0 = a quarter of the box diagonal
  //! Fit each frame's tilt 1-form (true: the frame is the texture the edit makes, Sec. 8.4.1; one
  //! back-substitution per frame) or displace along the edited directions directly (false: the same
  //! surface up to the fit's tolerance, no solve at all).
  bool refit = true;
  //! Decoding and re-encoding; the tilt system is always factored (TiltSolver::Direct) here.
  TextureOptions texture;
  //! Table; preset "thesis": the thesis' encoding and fit (TextureOptions' preset).
  static const OptionTable<AnimationOptions>& table();
};

//! Frames of an animation at interactive rates: the texture is decoded once and the base's tilt system
//! factored once (direct solver, whatever TextureOptions::solver says); each frame turns the cached
//! directions and re-solves (AnimationOptions::refit).
class TextureAnimator {
 public:
  //! \throw InvalidInput for bad options or a texture that does not match the base.
  TextureAnimator(const Mesh& base, const Texture& texture, const AnimationOptions& options = {});
  ~TextureAnimator();
  TextureAnimator(TextureAnimator&&) noexcept;
  TextureAnimator& operator=(TextureAnimator&&) noexcept;

  Texture texture(int frame);      //!< the edited texture of frame \p frame (0 ≤ frame < frames)
  MatrixX3d positions(int frame);  //!< the textured surface of frame \p frame: #V by 3
  int frames() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! Scale every height by \p factor.
Texture scale_height(const Texture& texture, double factor);

// ---------------------------------------------------------------------------------------------
// Texture file: PLY with the base mesh, vertex properties `height` and (with a lean) `lean` in
// radians, and an `edge` element with `vertex1`, `vertex2`, `tilt`.

void write_texture(const std::filesystem::path& path, const Mesh& base, const Texture& texture, bool binary = true);

struct TextureFile {
  Mesh base;
  Texture texture;
};
//! \throw IoError if the file lacks the height or the edge tilt, or an edge is not a mesh edge.
TextureFile read_texture(const std::filesystem::path& path);

}  // namespace geotex

