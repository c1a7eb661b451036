// Height-and-tilt geometric texture: extraction, reconstruction, editing, file I/O (thesis Sec. 8.3–8.4).
// The base shape is in base_shape.cpp, transfer in texture_transfer.cpp.

#include "geotex/texture/texture.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"

namespace geotex {

const EnumNames<TiltEncoding>& tilt_encoding_names() {
  static const EnumNames<TiltEncoding> n = {
      {"lean", TiltEncoding::Lean},
      {"lean-pushforward", TiltEncoding::LeanPushforward},
      {"one-form", TiltEncoding::OneForm},
      {"thesis", TiltEncoding::OneForm}};
  return n;
}

const EnumNames<TiltSolver>& tilt_solver_names() {
  static const EnumNames<TiltSolver> n = {{"iterative", TiltSolver::Iterative}, {"direct", TiltSolver::Direct}};
  return n;
}

const OptionTable<TextureOptions>& TextureOptions::table() {
  using O = TextureOptions;
  static const auto t = OptionTable<O>()
      .choice("tilt_encoding", &O::encoding, tilt_encoding_names(),
              "lean (the lean angle per vertex, kept under any deformation of the base; its direction turns with "
              "the base's rotation), lean-pushforward (the same angle, its direction pushed forward by the base's "
              "Jacobian: it turns with a stretch) or one-form (the thesis: the lean's size from the 1-form, divided "
              "by the base's area scale)",
              "Eq. (8.6-8.8)")
      .add("tangential_fit", &O::tangential_fit,
           "fit only the tilt's tangent components (all that decoding reads); false: the full fit of Eq. (5.81)",
           {}, "Eq. (8.2), (5.81)")
      .add("bound_tilt", &O::bound_tilt, "keep |c_ij| <= |e_ij| in the tilt fit", {}, "Sec. 8.5")
      .add("regularization", &O::regularization, "pull of the tilt fit towards the averaging estimate", non_negative(),
           "Eq. (5.80)")
      .add("height_weighted", &O::height_weighted, "weight each vertex's tilt equation by its height")
      .choice("tilt_solver", &O::solver, tilt_solver_names(),
              "iterative (CGLS to fit_tolerance, falls back to direct) or direct (sparse Cholesky)", "Eq. (8.2)")
      .add("fit_tolerance", &O::fit_tolerance,
           "iterative: stop when every reconstructed vertex is within this many mean edge lengths", positive())
      .add("max_iterations", &O::max_iterations, "iterative: CGLS iterations before falling back to direct",
           non_negative())
      .add("stall_iterations", &O::stall_iterations,
           "iterative: fall back to direct when the error shrank by less than 10 % over this many iterations",
           at_least(1))
      .preset("thesis", "the 1-form encoding of the lean (Eq. 8.6-8.8), full fit (Eq. 5.81), |c_ij| <= |e_ij| (Sec. 8.5), "
                        "direct solve",
              [](O& o) {
                o.encoding = TiltEncoding::OneForm;
                o.tangential_fit = false;
                o.bound_tilt = true;
                o.solver = TiltSolver::Direct;
              });
  return t;
}

namespace {

constexpr double kDeg = M_PI / 180.0;

double nonzero_sign(double x) { return x < 0 ? -1.0 : 1.0; }  // Sec. 8.3.2.2: sign(0) = +1

// \p base once \p o passed its table: the codec's members are built from both.
const Mesh& checked(const Mesh& base, const TextureOptions& o) {
  check_options(o);
  return base;
}

OneFormFitOptions fit_options(const TextureOptions& o) {
  OneFormFitOptions f;
  f.tangential = o.tangential_fit;
  f.bound_by_edge_length = o.bound_tilt;
  f.regularization = o.regularization;
  return f;
}

// Unit tangent direction of d at a vertex with normal n (zero if d is normal).
Vec3 tangent_direction(const Vec3& d, const Vec3& n) {
  const Vec3 t = d - d.dot(n) * n;
  const double l = t.norm();
  return l > 1e-12 ? Vec3(t / l) : Vec3::Zero();
}

// Rotate unit vector x towards tangent direction m (a plane spanned with the normal n) by angle θ:
// about the axis n × m, which turns n into cos θ n + sin θ m.
Vec3 turn_towards(const Vec3& x, const Vec3& n, const Vec3& m, double theta) {
  if (m.isZero()) return x;
  const Vec3 axis = n.cross(m).normalized();
  return Eigen::AngleAxisd(theta, axis) * x;
}

// Unit displacement direction from a vertex tilt t and the normal n (Eq. 8.8, DESIGN.md): t is made
// tangent; with lean < 0 (the thesis' encoding) it is clamped to length ≤ 1 and d̂ = cos α n + n × t,
// sin α = ‖t‖, cos α = sign √(1 − ‖t‖²); with a lean α ≥ 0 only t's direction counts:
// d̂ = sign cos α n + sin α (n × t)/‖t‖ (a vanishing t leaves d̂ = sign n).
Vec3 direction_from_tilt(Vec3 t, const Vec3& n, double sign, double lean = -1) {
  t -= t.dot(n) * n;
  const double l = t.norm();
  if (lean >= 0) {
    if (!(l > 1e-12)) return sign * n;
    return sign * std::cos(lean) * n + std::sin(lean) / l * n.cross(t);
  }
  if (l > 1) t /= l;
  const double s = std::min(1.0, l);
  return sign * std::sqrt(std::max(0.0, 1 - s * s)) * n + n.cross(t);
}

// Lean α ∈ [0, π/2] of a unit direction d from sign·n (Eq. 8.8): sin α = ‖d × n‖, cos α = |d·n|.
double lean_of(const Vec3& d, const Vec3& n) { return std::atan2(d.cross(n).norm(), std::abs(d.dot(n))); }

// The lean is stored per vertex (TiltEncoding::Lean, LeanPushforward).
bool stores_lean(TiltEncoding e) { return e != TiltEncoding::OneForm; }

// A unit vector perpendicular to unit n.
Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (a - a.dot(n) * n).normalized();
}

// Per vertex the frames (a0, n0 × a0) at the rest normal n0 and (a1, n1 × a1) at n1 (a1 = a0 turned by
// the smallest rotation taking n0 to n1) and the angle θ of the rotation part of the polar decomposition
// M = R S of the least-squares tangent Jacobian M (2 × 2 in those frames) of the one-ring: M minimises
// Σ_j ‖M p_j − q_j‖² / ‖p_j‖² over the edges ij, p_j, q_j the rest and current edges in the frames
// (each direction counts alike), and R = rot(θ), θ = atan2(M10 − M01, M00 + M11) the rotation nearest
// to M. Fewer than two independent edges: θ = 0 (parallel transport of the frame).
struct TangentTransport {
  MatrixX3d a0, a1;
  Eigen::VectorXd theta;
};
TangentTransport tangent_transport(const Mesh& mesh, const MatrixX3d& X0, const MatrixX3d& N0, const MatrixX3d& X1,
                                   const MatrixX3d& N1) {
  const Eigen::Index n = X0.rows();
  TangentTransport t{MatrixX3d(n, 3), MatrixX3d(n, 3), Eigen::VectorXd::Zero(n)};
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 n0 = N0.row(i), n1 = N1.row(i);
    const Vec3 a0 = any_perpendicular(n0);
    Vec3 a1 = Eigen::Quaterniond::FromTwoVectors(n0, n1) * a0;
    a1 = (a1 - a1.dot(n1) * n1).normalized();
    const Vec3 b0 = n0.cross(a0), b1 = n1.cross(a1);
    t.a0.row(i) = a0.transpose();
    t.a1.row(i) = a1.transpose();
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero(), C = Eigen::Matrix2d::Zero();
    for (auto h : mesh.voh_range(mesh.vertex_handle(static_cast<int>(i)))) {
      const int j = mesh.to_vertex_handle(h).idx();
      const Vec3 e0 = (X0.row(j) - X0.row(i)).transpose(), e1 = (X1.row(j) - X1.row(i)).transpose();
      const double w = e0.squaredNorm();
      if (!(w > 0)) continue;
      const Eigen::Vector2d p(e0.dot(a0), e0.dot(b0)), q(e1.dot(a1), e1.dot(b1));
      A += p * p.transpose() / w;
      C += q * p.transpose() / w;
    }
    if (!(std::abs(A.determinant()) > 1e-12 * A.squaredNorm())) continue;
    const Eigen::Matrix2d M = C * A.inverse();
    const double th = std::atan2(M(1, 0) - M(0, 1), M(0, 0) + M(1, 1));
    t.theta[i] = std::isfinite(th) ? th : 0.0;
  }
  return t;
}

Vec3 unit_or_throw(const Vec3& v, const char* what) {
  if (!(v.norm() > 0) || !v.allFinite()) throw InvalidInput(std::string(what) + ": direction must be a non-zero vector");
  return v.normalized();
}

// A texture with one height (and lean, if any) per vertex and one tilt per edge of \p base.
void require_matching(const Mesh& base, const Texture& t, const char* what) {
  const auto nv = static_cast<Eigen::Index>(base.n_vertices()), ne = static_cast<Eigen::Index>(base.n_edges());
  if (t.height.size() != nv || t.tilt.size() != ne || (t.lean.size() != 0 && t.lean.size() != nv) ||
      (t.rest.size() != 0 && t.rest.rows() != nv))
    throw InvalidInput(std::string(what) + ": the texture (" + std::to_string(t.height.size()) + " heights, " +
                       std::to_string(t.tilt.size()) + " tilts) does not match the base (" + std::to_string(nv) +
                       " vertices, " + std::to_string(ne) + " edges)");
}

}  // namespace

TextureCodec::TextureCodec(const Mesh& base, const TextureOptions& options)
    : base_(checked(base, options)),
      X_(positions(base)),
      N_(vertex_normals(base, options.normals)),
      options_(options),
      fitter_(base_, fit_options(options), N_),
      mean_edge_(mean_edge_length(base)) {}

Texture TextureCodec::extract(const MatrixX3d& textured) {
  if (textured.rows() != X_.rows())
    throw InvalidInput("texture extraction: the textured surface has " + std::to_string(textured.rows()) +
                       " vertices, the base " + std::to_string(X_.rows()) + " (same connectivity needed)");
  if (!textured.allFinite()) throw InvalidInput("texture extraction: non-finite coordinates");
  const Eigen::Index n = X_.rows();
  const bool lean = stores_lean(options_.encoding);
  Texture tex;
  tex.height.resize(n);
  if (lean) {
    tex.lean.resize(n);
    tex.rest = X_;
  }
  MatrixX3d T(n, 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 d = (textured.row(i) - X_.row(i)).transpose();  // Eq. (8.4)
    const Vec3 nrm = N_.row(i);
    const double len = d.norm();
    tex.height[i] = nonzero_sign(d.dot(nrm)) * len;                                // Eq. (8.5)
    T.row(i) = len > 0 ? Eigen::RowVector3d((d / len).cross(nrm).transpose()) : Eigen::RowVector3d::Zero();  // Eq. (8.6)
    if (lean) tex.lean[i] = len > 0 ? lean_of(d / len, nrm) : 0.0;
  }
  tex.tilt = encode_tilt(T, tex.height, tex.lean);  // Eq. (8.2)
  return tex;
}

MatrixX3d TextureCodec::tilt_vectors(const Eigen::VectorXd& tilt) const {
  if (tilt.size() != static_cast<Eigen::Index>(base_.n_edges()))
    throw InvalidInput("texture: expected one tilt per base edge (" + std::to_string(base_.n_edges()) + "), got " +
                       std::to_string(tilt.size()));
  const SparseMatrix& P = fitter_.matrix();
  const Eigen::VectorXd t = P * tilt;  // Eq. (5.79)
  const Eigen::Index n = X_.rows();
  MatrixX3d T(n, 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 nrm = N_.row(i);
    Vec3 v(t[i], t[n + i], t[2 * n + i]);
    v -= v.dot(nrm) * nrm;  // the tilt is tangent (Eq. 8.6)
    const double l = v.norm();
    if (l > 1) v /= l;      // ‖t‖ = sin α ≤ 1
    T.row(i) = v.transpose();
  }
  return T;
}

Eigen::VectorXd TextureCodec::encode_tilt(const MatrixX3d& T, const Eigen::VectorXd& heights,
                                          const Eigen::VectorXd& lean) {
  if (T.rows() != X_.rows()) throw InvalidInput("texture: expected one tilt vector per vertex");
  if (heights.size() != 0 && heights.size() != T.rows()) throw InvalidInput("texture: expected one height per vertex");
  if (lean.size() != 0 && lean.size() != T.rows()) throw InvalidInput("texture: expected one lean per vertex");
  const double hmax = heights.size() ? heights.cwiseAbs().maxCoeff() : 0.0;
  Eigen::VectorXd w;  // empty: unweighted
  if (options_.height_weighted && hmax > 0) {
    // Full fit: h² (a vertex's position error is |h_i| × its direction error, Eq. 8.8). Tangential fit:
    // |h|; the system is consistent, so the weights only steer CGLS (|h| needs the fewest iterations
    // on both the spiky shapes and igea; bench/texture.md).
    const Eigen::ArrayXd r = (heights / hmax).array().abs();
    w = (options_.tangential_fit ? r : r.square()) + 1e-4;
  }
  last_fit_ = TiltFitReport();
  // The tangential system is consistent (2#V equations, #E ≈ 3#V unknowns): its exact minimiser does
  // not depend on the weights, so the unweighted normal equations, factored once per base, serve every
  // fit (editing, animation frames) with one back-substitution.
  const bool weights_matter = w.size() && (!options_.tangential_fit || options_.bound_tilt);
  auto direct = [&] { return weights_matter ? fitter_.fit(T, w) : fitter_.fit(T); };
  if (options_.solver == TiltSolver::Direct || options_.bound_tilt) return direct();

  // Iterative: stop once the displacement directions the fitted tilt gives (Eq. 8.8) put every vertex
  // within fit_tolerance mean edges of where the target tilt puts it (|h_i| × direction error; with
  // no heights, the direction error itself). The normal part of P c, dropped when decoding, is not
  // driven to zero as tightly as by the exact minimiser (texture_test: TiltFieldIsTangentToTheBase).
  const Eigen::Index n = X_.rows();
  MatrixX3d D(n, 3);
  Eigen::VectorXd scale(n);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    const double sign = heights.size() ? nonzero_sign(heights[i]) : 1.0;
    const double a = lean.size() ? lean[i] : -1.0;
    D.row(i) = direction_from_tilt(T.row(i).transpose(), N_.row(i).transpose(), sign, a).transpose();
    scale[i] = heights.size() ? std::abs(heights[i]) / mean_edge_ : 1.0;
  }
  const int window = std::max(1, options_.stall_iterations / 10);  // in checks (one every 10 iterations)
  std::vector<double> history;
  bool met = false;
  auto monitor = [&](const Eigen::VectorXd&, const Eigen::VectorXd& Pc) {
    double err = 0;
#pragma omp parallel for schedule(static) reduction(max : err) if (n > 30000)
    for (Eigen::Index i = 0; i < n; ++i) {
      const double sign = heights.size() ? nonzero_sign(heights[i]) : 1.0;
      const double a = lean.size() ? lean[i] : -1.0;
      const Vec3 d = direction_from_tilt(Vec3(Pc[i], Pc[n + i], Pc[2 * n + i]), N_.row(i).transpose(), sign, a);
      err = std::max(err, scale[i] * (d - Vec3(D.row(i).transpose())).norm());
    }
    history.push_back(err);
    met = err <= options_.fit_tolerance;
    const size_t k = history.size();
    if (met || k <= static_cast<size_t>(window)) return met;
    // Give up (and solve directly) when the error shrank by less than 10 % over the window, or when
    // the rate over the window says the tolerance lies beyond max_iterations.
    const double ratio = err / history[k - 1 - window];
    if (!(ratio < 0.9)) return true;
    const double windows_left = std::log(options_.fit_tolerance / err) / std::log(ratio);
    return 10.0 * (k - 1) + windows_left * options_.stall_iterations > options_.max_iterations;
  };
  IterativeFitOptions io;
  io.max_iterations = options_.max_iterations;
  io.check_every = 10;
  IterativeFitResult r = fitter_.fit_iterative(T, w, monitor, io);
  last_fit_.iterations = r.iterations;
  last_fit_.error = history.empty() ? 0.0 : history.back();
  if (met) {
    last_fit_.iterative = true;
    return r.c;
  }
  return direct();  // stalled or out of iterations: the exact minimiser
}

MatrixX3d TextureCodec::directions(const Texture& tex) const {
  const Eigen::Index n = X_.rows();
  if (tex.height.size() != n)
    throw InvalidInput("texture: expected one height per base vertex (" + std::to_string(n) + "), got " +
                       std::to_string(tex.height.size()));
  const bool lean = stores_lean(options_.encoding) && tex.lean.size() != 0;
  if (lean && tex.lean.size() != n)
    throw InvalidInput("texture: expected one lean per base vertex (" + std::to_string(n) + "), got " +
                       std::to_string(tex.lean.size()));
  if (tex.rest.size() != 0 && (tex.rest.rows() != n || !tex.rest.allFinite()))
    throw InvalidInput("texture: expected " + std::to_string(n) + " finite rest positions, got " +
                       std::to_string(tex.rest.rows()));
  if (lean && options_.encoding == TiltEncoding::Lean && tex.rest.size() != 0 && tex.rest != X_) {
    // The direction in the base's tangent frame: decoded on the rest base (Eq. 5.79, 8.8 there), then
    // turned by the rotation part of the rest → current tangent Jacobian (issue 26).
    Mesh rest = base_;
    set_positions(rest, tex.rest);
    const MatrixX3d N0 = vertex_normals(rest, options_.normals);
    const MatrixX3d T0 = one_form_to_vertices(rest, tex.tilt);
    const TangentTransport tr = tangent_transport(base_, tex.rest, N0, X_, N_);
    MatrixX3d D(n, 3);
#pragma omp parallel for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i) {
      const Vec3 n0 = N0.row(i), n1 = N_.row(i);
      const double sign = nonzero_sign(tex.height[i]);
      Vec3 t0 = T0.row(i).transpose();
      t0 -= t0.dot(n0) * n0;
      if (!(t0.norm() > 1e-12)) {
        D.row(i) = (sign * n1).transpose();
        continue;
      }
      const Vec3 m0 = n0.cross(t0).normalized();  // the lean's direction at rest (Eq. 8.8)
      const Vec3 a0 = tr.a0.row(i), a1 = tr.a1.row(i);
      const Eigen::Vector2d p = Eigen::Rotation2Dd(tr.theta[i]) * Eigen::Vector2d(m0.dot(a0), m0.dot(n0.cross(a0)));
      const Vec3 m1 = p.x() * a1 + p.y() * n1.cross(a1);
      D.row(i) = (sign * std::cos(tex.lean[i]) * n1 + std::sin(tex.lean[i]) * m1).transpose();
    }
    return D;
  }
  if (tex.tilt.size() != static_cast<Eigen::Index>(base_.n_edges()))
    throw InvalidInput("texture: expected one tilt per base edge (" + std::to_string(base_.n_edges()) + "), got " +
                       std::to_string(tex.tilt.size()));
  const Eigen::VectorXd t = fitter_.matrix() * tex.tilt;  // Eq. (5.79)
  MatrixX3d D(n, 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    // With t = d̂ × n, d̂ = cos α n + n × t: the rotation of n is about t, not about n × t as printed in
    // Sec. 8.3.3 (see DESIGN.md; the round-trip test settles it).
    const Vec3 ti(t[i], t[n + i], t[2 * n + i]);
    D.row(i) = direction_from_tilt(ti, N_.row(i).transpose(), nonzero_sign(tex.height[i]), lean ? tex.lean[i] : -1.0)
                   .transpose();  // Eq. (8.8)
  }
  return D;
}

MatrixX3d TextureCodec::apply(const Texture& tex) const {
  const MatrixX3d D = directions(tex);
  MatrixX3d Y = X_;
  for (Eigen::Index i = 0; i < Y.rows(); ++i) Y.row(i) += std::abs(tex.height[i]) * D.row(i);
  return Y;
}

Texture extract_texture(const Mesh& base, const MatrixX3d& textured, const TextureOptions& options) {
  TextureCodec codec(base, options);
  return codec.extract(textured);
}

MatrixX3d apply_texture(const Mesh& base, const Texture& texture, const TextureOptions& options) {
  TextureOptions o = options;
  o.bound_tilt = false;  // nothing is fitted when only applying
  return TextureCodec(base, o).apply(texture);
}

Texture height_field_only(const Texture& texture) {
  Texture t = texture;
  t.tilt.setZero();
  t.lean.setZero();
  return t;
}

const OptionTable<TextureApplyOptions>& TextureApplyOptions::table() {
  using O = TextureApplyOptions;
  static const auto t = OptionTable<O>()
      .add("height_scale", &O::height_scale, "multiply every height by this (negative: bumps become dents)",
           between(-1e6, 1e6))
      .add("height_only", &O::height_only, "drop the tilt: a plain height field along the normals", {}, "Eq. (8.5)")
      .choice("tilt_encoding", &O::encoding, tilt_encoding_names(),
              "decoding on a deformed base: lean (the lean's direction turns with the base's rotation), "
              "lean-pushforward (with its Jacobian: it turns with a stretch) or one-form (the thesis)",
              "Eq. (8.8)");
  return t;
}

MatrixX3d apply_texture(const Mesh& base, const Texture& texture, const TextureApplyOptions& options) {
  TextureApplyOptions::table().check(options);
  require_matching(base, texture, "apply texture");
  Texture t = scale_height(texture, options.height_scale);
  if (options.height_only) t = height_field_only(t);
  TextureOptions o;
  o.encoding = options.encoding;
  return apply_texture(base, t, o);
}

// ---------------------------------------------------------------------------------------------
// Extraction from a textured mesh alone

const OptionTable<TextureExtractOptions>& TextureExtractOptions::table() {
  using O = TextureExtractOptions;
  static const auto t = OptionTable<O>()
      .nest(&O::base, BaseShapeOptions::table())
      .nest(&O::texture, TextureOptions::table())
      .add("project_onto_base", &O::project_onto_base,
           "with a given base of the same connectivity: project the textured vertices onto it along its Phong "
           "normals instead of using it vertex for vertex",
           {}, "Sec. 8.3.1, 5.2")
      .preset("thesis",
              "the thesis' base (implicit umbrella smoothing until the shape stops changing) and encoding (Eq. 8.6-8.8, "
              "full fit, |c_ij| <= |e_ij|, direct)",
              [](O& o) {
                BaseShapeOptions::table().apply_preset(o.base, "thesis");
                TextureOptions::table().apply_preset(o.texture, "thesis");
              });
  return t;
}

namespace {

bool same_connectivity(const Mesh& a, const Mesh& b) {
  return a.n_vertices() == b.n_vertices() && a.n_faces() == b.n_faces() && faces(a) == faces(b);
}

double median_of(Eigen::VectorXd v) {
  if (v.size() == 0) return 0;
  std::nth_element(v.data(), v.data() + v.size() / 2, v.data() + v.size());
  return v[v.size() / 2];
}

}  // namespace

TextureExtraction texture_extraction(const Mesh& textured, const Mesh* base, const TextureExtractOptions& options) {
  TextureExtractOptions::table().check(options);
  require_valid(textured, "texture extraction: textured mesh");
  TextureExtraction r;
  const MatrixX3d X = positions(textured);
  if (base) {
    require_valid(*base, "texture extraction: base");
    if (!options.project_onto_base && same_connectivity(*base, textured)) {
      r.source = BaseSource::Given;
      r.base = *base;
    } else {
      r.source = BaseSource::Projected;
      r.base = project_onto_base(textured, *base, &r.missed);
    }
    r.median_off_normal_deg = median_of(off_normal_angles(r.base, X));
  } else {
    BaseShapeOptions o = options.base;
    if (o.steps > 0) o.method = BaseMethod::Smoothing;  // a step count asks for the thesis' smoothing
    r.source = BaseSource::Automatic;
    r.shape = base_shape(textured, o);
    r.base = textured;
    set_positions(r.base, r.shape.positions);
    r.median_off_normal_deg = r.shape.median_off_normal_deg;
  }
  const double area = face_areas(textured).sum();
  r.base_area_ratio = area > 0 ? face_areas(r.base).sum() / area : 1.0;
  if (r.source == BaseSource::Automatic && r.base_area_ratio < kBaseAreaWarning)
    r.warnings.push_back(fmt::format(
        "the automatic base keeps {:.1f}% of the surface's area (less than {:.0f}%): part of the shape may have "
        "been read as texture; a smaller base scale or size share (--base-scale, --size-share) keeps more of it",
        100 * r.base_area_ratio, 100 * kBaseAreaWarning));
  TextureCodec codec(r.base, options.texture);
  r.texture = codec.extract(X);
  r.fit = codec.last_fit();
  const double h = mean_edge_length(r.base);
  r.max_error = (codec.apply(r.texture) - X).rowwise().norm().maxCoeff() / h;
  r.height_only_error = (codec.apply(height_field_only(r.texture)) - X).rowwise().norm().maxCoeff() / h;
  return r;
}

Texture TextureCodec::from_directions(const MatrixX3d& D, const Eigen::VectorXd& height) {
  const Eigen::Index n = X_.rows();
  if (D.rows() != n || height.size() != n)
    throw InvalidInput("texture: expected one direction and one height per base vertex (" + std::to_string(n) + ")");
  const bool lean = stores_lean(options_.encoding);
  Texture out;
  out.height.resize(n);
  if (lean) {
    out.lean.resize(n);
    out.rest = X_;
  }
  MatrixX3d T(n, 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 nrm = N_.row(i);
    Vec3 d = D.row(i).transpose();
    const double len = d.norm();
    if (len > 0) d /= len;
    out.height[i] = nonzero_sign(d.dot(nrm)) * std::abs(height[i]);  // Eq. (8.5)
    T.row(i) = d.cross(nrm).transpose();                              // Eq. (8.6)
    if (lean) out.lean[i] = len > 0 ? lean_of(d, nrm) : 0.0;
  }
  out.tilt = encode_tilt(T, out.height, out.lean);
  return out;
}

Texture set_tilt(TextureCodec& codec, const Texture& texture, const Vec3& direction, double angle_deg) {
  const Vec3 dir = unit_or_throw(direction, "set tilt");
  if (!std::isfinite(angle_deg)) throw InvalidInput("set tilt: the angle must be finite");
  const MatrixX3d& N = codec.normals();
  MatrixX3d D(N.rows(), 3);
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const Vec3 n = N.row(i);
    const Vec3 base = nonzero_sign(texture.height[i]) * n;
    // Turning −n towards m by θ leans it away from m; lean the tangential part towards m either way.
    const double theta = angle_deg * kDeg * nonzero_sign(texture.height[i]);
    D.row(i) = turn_towards(base, n, tangent_direction(dir, n), theta).transpose();
  }
  return codec.from_directions(D, texture.height);
}

namespace {

// Turn every direction D_i (in place) towards the tangent part of \p dir at n_i by theta(i) radians
// (OpenMP: theta must be thread-safe).
template <class Theta>
void turn_all(MatrixX3d& D, const MatrixX3d& N, const Vec3& dir, const Theta& theta) {
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const Vec3 n = N.row(i);
    D.row(i) = turn_towards(D.row(i).transpose(), n, tangent_direction(dir, n), theta(i)).transpose();
  }
}

// Wrap: θ_i = angle × |h_i| / max|h|.
void wrap_directions(MatrixX3d& D, const MatrixX3d& N, const Eigen::VectorXd& h, const Vec3& dir, double angle_deg) {
  const double hmax = h.size() ? h.cwiseAbs().maxCoeff() : 0.0;
  if (hmax > 0) turn_all(D, N, dir, [&](Eigen::Index i) { return angle_deg * kDeg * std::abs(h[i]) / hmax; });
}

// Wiggle: θ_i = amplitude × sin(2π (x_i·d̂ / wavelength − phase)) × |h_i| / max|h|.
void wiggle_directions(MatrixX3d& D, const MatrixX3d& N, const MatrixX3d& X, const Eigen::VectorXd& h, const Vec3& dir,
                       double amplitude_deg, double wavelength, double phase) {
  const double hmax = h.size() ? h.cwiseAbs().maxCoeff() : 0.0;
  if (hmax > 0)
    turn_all(D, N, dir, [&](Eigen::Index i) {
      const double wave = std::sin(2 * M_PI * (X.row(i).dot(dir) / wavelength - phase));
      return amplitude_deg * kDeg * wave * std::abs(h[i]) / hmax;
    });
}

}  // namespace

Texture wrap(TextureCodec& codec, const Texture& texture, const Vec3& direction, double angle_deg) {
  const Vec3 dir = unit_or_throw(direction, "wrap");
  if (!std::isfinite(angle_deg)) throw InvalidInput("wrap: the angle must be finite");
  MatrixX3d D = codec.directions(texture);
  wrap_directions(D, codec.normals(), texture.height, dir, angle_deg);
  return codec.from_directions(D, texture.height);
}

Texture wiggle(TextureCodec& codec, const Texture& texture, const Vec3& direction, double amplitude_deg,
               double wavelength, double phase) {
  const Vec3 dir = unit_or_throw(direction, "wiggle");
  if (!(wavelength > 0) || !std::isfinite(wavelength)) throw InvalidInput("wiggle: wavelength must be positive");
  if (!std::isfinite(amplitude_deg) || !std::isfinite(phase)) throw InvalidInput("wiggle: amplitude and phase must be finite");
  MatrixX3d D = codec.directions(texture);
  wiggle_directions(D, codec.normals(), positions(codec.base()), texture.height, dir, amplitude_deg, wavelength, phase);
  return codec.from_directions(D, texture.height);
}

const EnumNames<TextureEditKind>& texture_edit_names() {
  static const EnumNames<TextureEditKind> n = {{"set-tilt", TextureEditKind::SetTilt},
                                               {"wrap", TextureEditKind::Wrap},
                                               {"wiggle", TextureEditKind::Wiggle},
                                               {"scale-height", TextureEditKind::ScaleHeight}};
  return n;
}

const OptionTable<TextureEditOptions>& TextureEditOptions::table() {
  using O = TextureEditOptions;
  static const auto t = OptionTable<O>()
      .choice("op", &O::op, texture_edit_names(),
              "set-tilt (lean every displacement), wrap (bend, more towards the tips), wiggle (a wave in the tilt) "
              "or scale-height",
              "Sec. 8.4.1")
      .add("direction", &O::direction, "lean direction (projected onto each tangent plane)")
      .add("angle", &O::angle_deg, "degrees: set-tilt lean, wrap bend at the highest point, wiggle amplitude")
      .add("wavelength", &O::wavelength, "wiggle: wavelength along the direction (0: a quarter of the box diagonal)",
           non_negative())
      .add("phase", &O::phase, "wiggle: phase in wavelengths")
      .add("factor", &O::factor, "scale-height: the factor", between(-1e6, 1e6))
      .nest(&O::texture, TextureOptions::table())
      .preset("thesis", "the thesis' encoding and fit of the edited tilt (Eq. 8.6-8.8, 5.81; Sec. 8.5)",
              [](O& o) { TextureOptions::table().apply_preset(o.texture, "thesis"); });
  return t;
}

Texture edit_texture(const Mesh& base, const Texture& texture, const TextureEditOptions& o) {
  TextureEditOptions::table().check(o);
  require_matching(base, texture, "edit texture");
  if (o.op == TextureEditKind::ScaleHeight) return scale_height(texture, o.factor);
  TextureCodec codec(base, o.texture);
  switch (o.op) {
    case TextureEditKind::SetTilt: return set_tilt(codec, texture, o.direction, o.angle_deg);
    case TextureEditKind::Wrap: return wrap(codec, texture, o.direction, o.angle_deg);
    default: break;
  }
  const double wavelength = o.wavelength > 0 ? o.wavelength : 0.25 * bounding_box(base).diagonal();
  return wiggle(codec, texture, o.direction, o.angle_deg, wavelength, o.phase);
}

// ---------------------------------------------------------------------------------------------
// Animation

const EnumNames<AnimationKind>& animation_kind_names() {
  static const EnumNames<AnimationKind> n = {
      {"wiggle", AnimationKind::Wiggle}, {"wrap", AnimationKind::Sway}, {"sway", AnimationKind::Sway}, {"grow", AnimationKind::Grow}};
  return n;
}

const OptionTable<AnimationOptions>& AnimationOptions::table() {
  using O = AnimationOptions;
  static const auto t = OptionTable<O>()
      .choice("op", &O::kind, animation_kind_names(),
              "wiggle (travelling wave), wrap (sway back and forth) or grow (heights 0 -> 1 -> 0)", "Sec. 8.4.1")
      .add("frames", &O::frames, "number of frames (one period)", between(1, 100000))
      .add("direction", &O::direction, "direction the texture leans or the wave travels (projected onto each tangent plane)")
      .add("angle", &O::angle_deg, "degrees: wave amplitude or sway angle at the highest point", any_value())
      .add("wavelength", &O::wavelength, "wiggle: wavelength along the direction (0: a quarter of the box diagonal)",
           non_negative())
      .add("refit", &O::refit,
           "fit each frame's tilt 1-form (factored once per base); false: displace along the edited directions")
      .nest(&O::texture, TextureOptions::table())
      .preset("thesis", "the thesis' encoding and fit of each frame's tilt (Eq. 8.6-8.8, 5.81; Sec. 8.5)",
              [](O& o) { TextureOptions::table().apply_preset(o.texture, "thesis"); });
  return t;
}

struct TextureAnimator::Impl {
  TextureCodec codec;
  Texture texture;
  AnimationOptions options;
  MatrixX3d X, D;  // base positions, decoded directions (once)
  Vec3 dir;
  double wavelength = 1;
  Impl(const Mesh& base, const TextureOptions& o) : codec(base, o) {}
};

TextureAnimator::TextureAnimator(const Mesh& base, const Texture& texture, const AnimationOptions& options) {
  AnimationOptions::table().check(options);
  require_matching(base, texture, "animation");
  TextureOptions o = options.texture;
  // One factorization of the tilt system for every frame (the tangential fit's exact minimiser does not
  // depend on the weights: TextureCodec::encode_tilt); CGLS would restart from scratch each frame.
  o.solver = TiltSolver::Direct;
  impl_ = std::make_unique<Impl>(base, o);
  Impl& m = *impl_;
  m.texture = texture;
  m.options = options;
  m.X = geotex::positions(base);
  m.D = m.codec.directions(texture);
  m.dir = unit_or_throw(options.direction, "animation");
  m.wavelength = options.wavelength > 0 ? options.wavelength : 0.25 * bounding_box(base).diagonal();
}

TextureAnimator::~TextureAnimator() = default;
TextureAnimator::TextureAnimator(TextureAnimator&&) noexcept = default;
TextureAnimator& TextureAnimator::operator=(TextureAnimator&&) noexcept = default;

int TextureAnimator::frames() const { return impl_->options.frames; }

Texture TextureAnimator::texture(int frame) {
  Impl& m = *impl_;
  const double s = double(frame) / m.options.frames;
  if (m.options.kind == AnimationKind::Grow) return scale_height(m.texture, 0.5 * (1 - std::cos(2 * M_PI * s)));
  MatrixX3d D = m.D;
  if (m.options.kind == AnimationKind::Wiggle)
    wiggle_directions(D, m.codec.normals(), m.X, m.texture.height, m.dir, m.options.angle_deg, m.wavelength, s);
  else
    wrap_directions(D, m.codec.normals(), m.texture.height, m.dir, m.options.angle_deg * std::sin(2 * M_PI * s));
  return m.codec.from_directions(D, m.texture.height);
}

MatrixX3d TextureAnimator::positions(int frame) {
  Impl& m = *impl_;
  if (m.options.refit || m.options.kind == AnimationKind::Grow) return m.codec.apply(texture(frame));
  const double s = double(frame) / m.options.frames;
  MatrixX3d D = m.D;
  if (m.options.kind == AnimationKind::Wiggle)
    wiggle_directions(D, m.codec.normals(), m.X, m.texture.height, m.dir, m.options.angle_deg, m.wavelength, s);
  else
    wrap_directions(D, m.codec.normals(), m.texture.height, m.dir, m.options.angle_deg * std::sin(2 * M_PI * s));
  return m.X + m.texture.height.cwiseAbs().asDiagonal() * D;
}

Texture scale_height(const Texture& texture, double factor) {
  if (!std::isfinite(factor)) throw InvalidInput("scale height: factor must be finite");
  Texture t = texture;
  t.height *= factor;
  return t;
}

void write_texture(const std::filesystem::path& path, const Mesh& base, const Texture& texture, bool binary) {
  if (texture.height.size() != static_cast<Eigen::Index>(base.n_vertices()) ||
      texture.tilt.size() != static_cast<Eigen::Index>(base.n_edges()) ||
      (texture.lean.size() != 0 && texture.lean.size() != texture.height.size()) ||
      (texture.rest.size() != 0 && texture.rest.rows() != texture.height.size()))
    throw InvalidInput("write texture: sizes do not match the base mesh");
  PlyExtras ex;
  ex.vertex_scalars["height"] = std::vector<double>(texture.height.data(), texture.height.data() + texture.height.size());
  if (texture.lean.size())
    ex.vertex_scalars["lean"] = std::vector<double>(texture.lean.data(), texture.lean.data() + texture.lean.size());
  // A rest pose other than the base itself (a texture written over a deformed base): rest_x, rest_y, rest_z.
  if (texture.rest.size() && texture.rest != positions(base))
    for (int k = 0; k < 3; ++k) {
      const Eigen::VectorXd c = texture.rest.col(k);
      ex.vertex_scalars[std::string("rest_") + "xyz"[k]] = std::vector<double>(c.data(), c.data() + c.size());
    }
  PlyExtras::Element e;
  e.name = "edge";
  const MatrixX2i E = edges(base);
  e.int_props["vertex1"] = std::vector<int>(E.rows());
  e.int_props["vertex2"] = std::vector<int>(E.rows());
  for (Eigen::Index k = 0; k < E.rows(); ++k) {
    e.int_props["vertex1"][k] = E(k, 0);
    e.int_props["vertex2"][k] = E(k, 1);
  }
  e.double_props["tilt"] = std::vector<double>(texture.tilt.data(), texture.tilt.data() + texture.tilt.size());
  ex.elements.push_back(std::move(e));
  write_ply(base, path, ex, binary);
}

TextureFile read_texture(const std::filesystem::path& path) {
  TextureFile out;
  ReadOptions ro;
  ro.strict = true;  // a dropped face would shift the edges the tilt refers to
  out.base = read_mesh(path, ro);
  const PlyData data = read_ply_data(path);
  const PlyElement* v = data.find("vertex");
  if (!v || !v->scalars.count("height"))
    throw IoError(path.string() + ": not a texture file (no vertex property 'height')");
  const auto& h = v->scalars.at("height");
  if (h.size() != out.base.n_vertices()) throw IoError(path.string() + ": height count does not match the vertices");
  out.texture.height = Eigen::Map<const Eigen::VectorXd>(h.data(), h.size());
  if (v->scalars.count("lean")) {  // absent in the thesis' encoding and older files
    const auto& a = v->scalars.at("lean");
    if (a.size() != h.size()) throw IoError(path.string() + ": lean count does not match the vertices");
    out.texture.lean = Eigen::Map<const Eigen::VectorXd>(a.data(), a.size());
    // The rest pose of the lean's direction: the stored one, else the base itself.
    out.texture.rest = positions(out.base);
    for (int k = 0; k < 3; ++k) {
      const auto it = v->scalars.find(std::string("rest_") + "xyz"[k]);
      if (it == v->scalars.end()) continue;
      if (it->second.size() != h.size()) throw IoError(path.string() + ": rest count does not match the vertices");
      out.texture.rest.col(k) = Eigen::Map<const Eigen::VectorXd>(it->second.data(), it->second.size());
    }
  }
  const EdgeValues ev = read_edge_values(path, "tilt");
  if (ev.values.size() != static_cast<Eigen::Index>(out.base.n_edges()))
    throw IoError(path.string() + ": " + std::to_string(ev.values.size()) + " tilt values for " +
                  std::to_string(out.base.n_edges()) + " edges");
  // Match each stored edge to the rebuilt mesh's edge (and orientation): edge order is not promised.
  out.texture.tilt.setZero(out.base.n_edges());
  std::vector<char> seen(out.base.n_edges(), 0);
  const int nv = static_cast<int>(out.base.n_vertices());
  for (Eigen::Index k = 0; k < ev.edges.rows(); ++k) {
    const int a = ev.edges(k, 0), b = ev.edges(k, 1);
    if (a < 0 || b < 0 || a >= nv || b >= nv) throw IoError(path.string() + ": edge vertex index out of range");
    const auto hh = out.base.find_halfedge(out.base.vertex_handle(a), out.base.vertex_handle(b));
    if (!hh.is_valid()) throw IoError(path.string() + ": edge " + std::to_string(k) + " is not an edge of the mesh");
    const auto eh = out.base.edge_handle(hh);
    seen[eh.idx()] = 1;
    out.texture.tilt[eh.idx()] = out.base.halfedge_handle(eh, 0) == hh ? ev.values[k] : -ev.values[k];
  }
  if (std::find(seen.begin(), seen.end(), 0) != seen.end())
    throw IoError(path.string() + ": the edge element does not cover every mesh edge");
  return out;
}

}  // namespace geotex
