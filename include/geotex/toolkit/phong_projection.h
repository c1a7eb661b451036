#pragma once
//! \file phong_projection.h Projection of a point onto a triangle mesh along the Phong-interpolated
//! (vertex-normal-blended) normal field, thesis Sec. 5.2.
//!
//! For a point p and a triangle (a, b, c) with vertex normals (n_a, n_b, n_c), find q = u a + v b + w c
//! with p − q parallel to n_q = u n_a + v n_b + w n_c (Eq. 5.25–5.27). Two solvers:
//!  - Newton's method on f(u, v) = ‖F(u, v)‖² (Eq. 5.36–5.45), as in the literature;
//!  - the analytic solution (Eq. 5.46–5.63): p = q + d n_q is a cubic in d, whose every real root is a
//!    candidate, inside or outside the triangle.

#include <array>
#include <vector>

#include "geotex/core/options.h"
#include "geotex/core/mesh.h"
#include "geotex/core/spatial.h"

namespace geotex {

//! A triangle with vertex normals, and the per-triangle terms of the cubic's coefficients that do not
//! depend on p (Eq. 5.51–5.54: "three vectors and four scalars can be pre-computed").
struct PhongTriangle {
  Vec3 a, b, c;        //!< corners
  Vec3 na, nb, nc;     //!< vertex normals (any length; usually unit)
  double r3 = 0;       //!< Eq. (5.51): −[n_a, n_b, n_c]
  Vec3 k2, k1, k0;     //!< vectors dotted with p in Eq. (5.52), (5.53), (5.54)
  double s2 = 0, s1 = 0, s0 = 0;  //!< scalars subtracted in Eq. (5.52), (5.53), (5.54)

  PhongTriangle() = default;
  PhongTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb, const Vec3& nc);

  //! Coefficients (r0, r1, r2, r3) of the cubic r3 d³ + r2 d² + r1 d + r0 = 0 for point p (Eq. 5.50).
  std::array<double, 4> cubic(const Vec3& p) const;
};

//! One solution candidate of the Phong projection on one triangle.
struct PhongCandidate {
  double d = 0;               //!< p = q + d n_q (Eq. 5.46); n_q is the blended, unnormalized normal
  Vec3 bary = Vec3::Zero();   //!< (u, v, w): weights of a, b, c (Eq. 5.56–5.58)
  Vec3 point = Vec3::Zero();  //!< q
  Vec3 normal = Vec3::Zero(); //!< n_q (Eq. 5.26), unnormalized
  bool inside = false;        //!< all barycentric coordinates ≥ −tolerance
};

//! The analytic solution (Eq. 5.46–5.63): every real root of the cubic, sorted by |d|, with its
//! barycentric coordinates and whether it lies inside the triangle (coordinates ≥ −\p inside_tol).
//! Roots whose shifted triangle is degenerate (Eq. 5.56's denominator vanishes) are left out.
std::vector<PhongCandidate> phong_project_analytic(const Vec3& p, const PhongTriangle& t,
                                                   double inside_tol = 1e-9);

//! The bivariate quadratic F(u, v) = (p − q(u,v)) × n(u,v) of Eq. (5.28)–(5.35) and its derivatives.
//! (Eq. 5.28's bracket is p − (u a + v b + (1−u−v) c); Eq. 5.32 has p − c, not p − b; Eq. 5.39 is
//! F_u = d_u + 2u d_uu + v d_uv: see DESIGN.md and the finite-difference test.)
struct PhongQuadratic {
  Vec3 d0, du, dv, duu, duv, dvv;  //!< Eq. (5.30)–(5.35)
  PhongQuadratic(const Vec3& p, const PhongTriangle& t);
  Vec3 F(double u, double v) const;   //!< Eq. (5.29)
  Vec3 Fu(double u, double v) const;  //!< Eq. (5.39)
  Vec3 Fv(double u, double v) const;  //!< Eq. (5.40)
  double f(double u, double v) const { return F(u, v).squaredNorm(); }  //!< Eq. (5.36)
  Eigen::Vector2d gradient(double u, double v) const;  //!< Eq. (5.37)
  Eigen::Matrix2d hessian(double u, double v) const;   //!< Eq. (5.38) with (5.41)–(5.43)
};

struct PhongNewtonOptions {
  int max_iterations = 30;             //!< Newton steps (Eq. 5.44–5.45)
  double step_tolerance = 1e-13;       //!< stop when the step ‖h‖ falls below this
  double residual_tolerance = 1e-10;   //!< converged when ‖F‖ ≤ this × (scale of p − q and n)²
  Eigen::Vector2d start{1.0 / 3.0, 1.0 / 3.0};  //!< (u0, v0): the barycentre, as in the thesis
};

struct PhongNewtonResult {
  PhongCandidate candidate;  //!< where the iteration ended (d from the least-squares fit of p − q = d n_q)
  bool converged = false;    //!< ‖F‖ small at the end
  int iterations = 0;
  double residual = 0;       //!< ‖F(u, v)‖ at the end
};

//! Newton's method on f = ‖F‖² from \p options.start (Eq. 5.36–5.45). Plain Newton, as in the
//! thesis: it may stop at an outside solution, or between solutions, even when an inside one exists.
PhongNewtonResult phong_project_newton(const Vec3& p, const PhongTriangle& t,
                                       const PhongNewtonOptions& options = {});

struct PhongProjectionOptions {
  //! Candidate triangles: those whose box lies within search_factor × (closest distance) +
  //! search_margin × (mean edge length) of the point; widened (×2, up to 4 times) if none gives an
  //! inside solution.
  double search_factor = 1.5;
  double search_margin = 1.0;
  double inside_tol = 1e-9;  //!< barycentric tolerance for "inside"
  static const OptionTable<PhongProjectionOptions>& table();
};

//! A point projected onto a mesh along the Phong normal field.
struct PhongHit {
  bool found = false;        //!< an inside solution was found (else face = −1 and the rest is the
                             //!< closest point, with d its signed distance along the face normal)
  int face = -1;
  Vec3 bary = Vec3::Zero();  //!< weights of the face's corners in faces(mesh) order
  Vec3 point = Vec3::Zero(); //!< q
  Vec3 normal = Vec3::Zero();//!< unit Phong normal n_q / ‖n_q‖
  double d = 0;              //!< p = q + d n_q with the unnormalized n_q (Eq. 5.46)
  double distance = 0;       //!< signed ‖p − q‖ (sign of d)
};

//! Point-to-mesh projection under the Phong normal field, with the per-triangle terms precomputed
//! once. Among the inside candidates of the triangles near p it picks the smallest |d| (Sec. 5.2.4).
//! The search visits the faces nearest first and skips every subtree whose cone of vertex normals
//! cannot point at p (a projection satisfies p − q = d n_q): for a far point, whose nearest faces are
//! all about equally near, only the faces facing it are solved (cost log #F, not #F per point).
class PhongProjector {
 public:
  //! \param mesh base surface; \param normals #V by 3 vertex normals (default: angle-weighted, unit).
  explicit PhongProjector(const Mesh& mesh, const MatrixX3d& normals = MatrixX3d(),
                          const PhongProjectionOptions& options = {});

  //! Project one point. Thread-safe (const).
  PhongHit project(const Vec3& p) const;
  //! Project #P by 3 points (OpenMP). \return one hit per row.
  std::vector<PhongHit> project(const MatrixX3d& P) const;

  const PhongTriangle& triangle(int f) const { return tris_[f]; }
  const MatrixX3i& triangles() const { return tree_.triangles(); }
  const MatrixX3d& normals() const { return N_; }

 private:
  //! Where a face's (or a subtree's) projections can come from: p − q = d n_q with q within
  //! \p radius of \p center and n_q within \p angle of ±\p axis (angle ≥ π/2: anywhere).
  struct NormalCone {
    Vec3 axis = Vec3::Zero();
    double angle = 4;  // radians; ≥ π/2 prunes nothing
    Vec3 center = Vec3::Zero();
    double radius = 0;
  };
  static NormalCone merge(const NormalCone& x, const NormalCone& y);
  static bool may_project_from(const NormalCone& c, const Vec3& p);
  void build_cones();
  bool solves(const Vec3& p, const PhongCandidate& c) const;

  TriangleTree tree_;
  MatrixX3d N_;
  std::vector<NormalCone> face_cone_, node_cone_;  // per face, per tree node
  std::vector<PhongTriangle> tris_;
  PhongProjectionOptions options_;
  double mean_edge_ = 1;
};

}  // namespace geotex
