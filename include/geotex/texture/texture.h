#pragma once
//! \file texture.h Height-and-tilt geometric texture (thesis ch. 8): a pseudo-height per vertex and a
//! tilt per edge (a discrete 1-form) over a base mesh. Extract, reconstruct, edit, animate, store,
//! re-apply to a deformed base, and transfer between disk patches of two surfaces.
//!
//! Conventions: the texture lives on the base mesh's vertices (height, #V) and edges (tilt, #E, in
//! OpenMesh edge order, oriented as edges(mesh)). Normals are the base's vertex normals
//! (TextureOptions::normals), recomputed from whatever base the texture is applied to.

#include <filesystem>
#include <vector>

#include "geotex/core/geometry.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/core/mesh.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/core/progress.h"

namespace geotex {

// ---------------------------------------------------------------------------------------------
// Base shape (Sec. 8.3.1)

struct BaseShapeOptions {
  //! Umbrella (default) or cotangent (mean-curvature flow proper, Eq. 5.11). Overhanging textures give
  //! negative cotangent weights and an indefinite system (seen on spiky-sphere), so umbrella is the default.
  LaplacianType laplacian = LaplacianType::Umbrella;
  double lambda = 1.0;          //!< implicit step (umbrella: dimensionless; cotangent: in squared mean edges)
  int steps = 0;                //!< number of steps; 0 = automatic: step until the shape stops changing
  int max_steps = 30;           //!< automatic mode: at most this many steps
  double stop_tolerance = 0.05; //!< automatic mode: stop when a step moves no vertex more than this × mean edge
  ProgressFn progress;          //!< called after each step
};

//! Base shape by implicit Laplacian smoothing (Eq. 5.14) keeping vertex correspondence (Sec. 8.3.1).
//! \return #V by 3 positions, same connectivity and order as \p textured.
MatrixX3d extract_base_shape(const Mesh& textured, const BaseShapeOptions& options = {});

//! A base of any connectivity: each vertex of \p textured projected onto \p base along the Phong
//! normal field (Sec. 5.2). \return a mesh with textured's connectivity at the projected points;
//! \p missed (optional) counts vertices with no inside solution (they take the closest point).
Mesh project_onto_base(const Mesh& textured, const Mesh& base, size_t* missed = nullptr);

// ---------------------------------------------------------------------------------------------
// Representation (Sec. 8.3.2–8.3.3)

//! texture = ({h_i}, {c_ij}) (Eq. 8.7).
struct Texture {
  Eigen::VectorXd height;  //!< #V pseudo-heights h_i = sign(d_i·n_i) ‖d_i‖ (Eq. 8.5), sign never 0
  Eigen::VectorXd tilt;    //!< #E tilt 1-form coefficients c_ij of t_i = d̂_i × n_i (Eq. 8.6)
};

//! How the tilt 1-form is fitted (Eq. 8.2). Both minimise the same least-squares objective (Eq. 5.81).
enum class TiltSolver {
  //! CGLS from the averaging estimate (Eq. 5.80), stopped once the reconstruction it gives is within
  //! TextureOptions::fit_tolerance of the target; falls back to Direct when it stalls or runs out of
  //! iterations. No factorization: ~10× faster at 10^5–10^6 vertices (bench/texture.md).
  Iterative,
  Direct,  //!< sparse Cholesky of the #E × #E normal equations: the exact minimiser
};

struct TextureOptions {
  NormalWeighting normals = NormalWeighting::Angle;  //!< base vertex normals n_i
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

  //! Tilt vectors at vertices (Eq. 5.79), made tangent and clamped to length ≤ 1. \return #V by 3.
  MatrixX3d tilt_vectors(const Eigen::VectorXd& tilt) const;
  //! Encode tilt vectors at vertices as a 1-form (Eq. 8.2), weighted by \p heights when
  //! TextureOptions::height_weighted (pass an empty vector for an unweighted fit). \return #E.
  Eigen::VectorXd encode_tilt(const MatrixX3d& tilt_vectors, const Eigen::VectorXd& heights = {});
  //! Unit displacement directions d̂_i = cos α n_i + n_i × t_i with sin α = ‖t_i‖, cos α = sign(h_i)
  //! √(1 − ‖t_i‖²) (Eq. 8.8; the rotation is about t_i — DESIGN.md on Sec. 8.3.3). \return #V by 3.
  MatrixX3d directions(const Texture& texture) const;

  const Mesh& base() const { return base_; }
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

//! The same texture with the tilt dropped: a plain height field along the normals.
Texture height_field_only(const Texture& texture);

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

//! Scale every height by \p factor.
Texture scale_height(const Texture& texture, double factor);

// ---------------------------------------------------------------------------------------------
// Texture file: PLY with the base mesh, a vertex property `height` and an `edge` element with
// `vertex1`, `vertex2`, `tilt`.

void write_texture(const std::filesystem::path& path, const Mesh& base, const Texture& texture, bool binary = true);

struct TextureFile {
  Mesh base;
  Texture texture;
};
//! \throw IoError if the file lacks the height or the edge tilt, or an edge is not a mesh edge.
TextureFile read_texture(const std::filesystem::path& path);

// ---------------------------------------------------------------------------------------------
// Transfer (Sec. 8.3.3)

//! A disk-shaped piece of a mesh and where it came from.
struct DiskPatch {
  Mesh mesh;
  std::vector<int> vertices;  //!< patch vertex → original vertex
  std::vector<int> faces;     //!< patch face → original face
};

//! The faces within geodesic (edge-path) distance \p radius of vertex \p center, as a disk patch.
//! \throw InvalidInput if the centre is out of range or the result is not a disk (one boundary loop,
//! Euler characteristic 1).
DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius);

struct TransferOptions {
  int source_center = 0;       //!< source base vertex at the patch centre
  double source_radius = 0;    //!< geodesic radius of the source patch
  int target_center = 0;       //!< target base vertex at the patch centre
  double target_radius = 0;    //!< geodesic radius of the target patch
  double rotation_deg = 0;     //!< rotate the source disk by this angle before resampling
  int edge_samples = 5;        //!< samples per target edge for the tilt (the thesis uses 5)
  TextureOptions texture;      //!< normals used on both surfaces
};

struct TransferResult {
  Texture texture;             //!< on the whole target base (zero outside the patch)
  DiskPatch source_patch, target_patch;
  size_t target_vertices = 0;  //!< target vertices that received a height
};

//! Transfer the texture of a disk patch of \p source_base to a disk patch of \p target_base through
//! the discrete conformal maps of both patches to the unit disk (Eq. 5.85): heights by barycentric
//! resampling, tilt by sampling each target edge at edge_samples points, evaluating the Whitney-
//! interpolated source field (Eq. 8.3), carrying it through the two maps and integrating along the edge.
TransferResult transfer_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                                const TransferOptions& options);

}  // namespace geotex
