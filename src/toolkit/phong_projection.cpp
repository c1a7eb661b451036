// Phong-normal projection, thesis Sec. 5.2.

#include "geotex/toolkit/phong_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {

const OptionTable<PhongProjectionOptions>& PhongProjectionOptions::table() {
  using O = PhongProjectionOptions;
  static const auto t = OptionTable<O>()
      .add("search_factor", &O::search_factor, "candidate triangles within this x the closest distance (+ margin)", positive())
      .add("search_margin", &O::search_margin, "candidate search margin, in mean edge lengths", non_negative())
      .add("inside_tol", &O::inside_tol, "barycentric tolerance for a point inside a triangle", non_negative(), "Sec. 5.2");
  return t;
}
namespace {

double triple(const Vec3& x, const Vec3& y, const Vec3& z) { return x.dot(y.cross(z)); }  // Eq. (5.55)

double eval_cubic(const std::array<double, 4>& r, double d) { return ((r[3] * d + r[2]) * d + r[1]) * d + r[0]; }
double eval_dcubic(const std::array<double, 4>& r, double d) { return (3 * r[3] * d + 2 * r[2]) * d + r[1]; }

// A root of the cubic in [lo, hi] where it changes sign: Newton steps kept inside the bracket,
// bisection when a step would leave it (rtsafe). Robust for any coefficient scale.
double bracketed_root(const std::array<double, 4>& r, double lo, double hi) {
  double flo = eval_cubic(r, lo);
  if (flo == 0) return lo;
  double x = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double fx = eval_cubic(r, x);
    if (fx == 0) return x;
    if ((fx < 0) == (flo < 0)) {
      lo = x;
      flo = fx;
    } else {
      hi = x;
    }
    const double df = eval_dcubic(r, x);
    double next = df != 0 ? x - fx / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 4 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x))) return next;
    x = next;
  }
  return x;
}

// Real roots of r3 d³ + r2 d² + r1 d + r0: the cubic is monotone between its critical points, so each
// sign change between consecutive critical points (and ±Cauchy bound) brackets exactly one root.
int real_roots(const std::array<double, 4>& r, double out[3]) {
  const double a3 = std::abs(r[3]);
  const double amax = std::max({std::abs(r[0]), std::abs(r[1]), std::abs(r[2])});
  if (a3 == 0 || a3 < 1e-300) {
    // Quadratic (parallel normals: the shifted triangles keep their orientation's scale).
    if (r[2] == 0) {
      if (r[1] == 0) return 0;
      out[0] = -r[0] / r[1];
      return 1;
    }
    const double disc = r[1] * r[1] - 4 * r[2] * r[0];
    if (disc < 0) return 0;
    const double q = -0.5 * (r[1] + std::copysign(std::sqrt(disc), r[1]));
    int n = 0;
    if (q != 0) out[n++] = r[0] / q;
    out[n++] = q / r[2];
    if (n == 2 && out[0] == out[1]) n = 1;
    return n;
  }
  const double bound = 1 + amax / a3;
  // Critical points: roots of 3 r3 d² + 2 r2 d + r1 (stable quadratic formula).
  double crit[2];
  int nc = 0;
  const double A = 3 * r[3], B = 2 * r[2], C = r[1];
  const double disc = B * B - 4 * A * C;
  if (disc > 0) {
    const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    double x1 = q / A, x2 = q != 0 ? C / q : x1;
    if (x1 > x2) std::swap(x1, x2);
    crit[nc++] = std::clamp(x1, -bound, bound);
    crit[nc++] = std::clamp(x2, -bound, bound);
  }
  double knots[4];
  int nk = 0;
  knots[nk++] = -bound;
  for (int i = 0; i < nc; ++i) knots[nk++] = crit[i];
  knots[nk++] = bound;
  int n = 0;
  bool bracketed[3] = {false, false, false};  // interval i (between knots i and i+1) held a root
  for (int i = 0; i + 1 < nk; ++i) {
    const double lo = knots[i], hi = knots[i + 1];
    if (!(hi > lo)) continue;
    const double flo = eval_cubic(r, lo), fhi = eval_cubic(r, hi);
    if ((flo < 0) != (fhi < 0) || fhi == 0) {
      if (fhi == 0 && i + 2 < nk) continue;  // counted as the next interval's left end
      out[n++] = bracketed_root(r, lo, hi);
      bracketed[i] = true;
    }
  }
  // A double root at a critical point (tangency) changes no sign: accept it when the value vanishes
  // to rounding and no root was bracketed on either side of it (two close simple roots are not one).
  for (int i = 0; i < nc && n < 3; ++i) {
    if (bracketed[i] || bracketed[i + 1]) continue;
    const double x = crit[i];
    const double scale = ((a3 * std::abs(x) + std::abs(r[2])) * std::abs(x) + std::abs(r[1])) * std::abs(x) + std::abs(r[0]);
    if (std::abs(eval_cubic(r, x)) <= 1e-14 * scale) {
      bool dup = false;
      for (int k = 0; k < n; ++k) dup |= std::abs(out[k] - x) <= 1e-9 * std::max(1.0, std::abs(x));
      if (!dup) out[n++] = x;
    }
  }
  return n;
}

// Barycentric coordinates of p in the triangle shifted by d (Eq. 5.56–5.63); false if degenerate.
bool shifted_bary(const Vec3& p, const PhongTriangle& t, double d, Vec3& bary) {
  const Vec3 ad = t.a + d * t.na, bd = t.b + d * t.nb, cd = t.c + d * t.nc;
  const Vec3 ea = ad - cd, eb = bd - cd, ep = p - cd;
  const double taa = ea.dot(ea), tbb = eb.dot(eb), tab = ea.dot(eb);  // Eq. (5.59)–(5.61)
  const double tpa = ep.dot(ea), tpb = ep.dot(eb);                    // Eq. (5.62)–(5.63)
  const double den = taa * tbb - tab * tab;
  if (!(den > 1e-24 * taa * tbb) || !std::isfinite(den)) return false;
  if (den < 1e-4 * taa * tbb) {
    // A sliver (edges within 0.6° of each other): den = |ea|²|eb|² sin²θ cancels, its relative error
    // eps / sin²θ (1e-9 on a needle of aspect 10^4 put its own vertex outside it, the inside test
    // failed and the search went on over every face nearby, issue 30); the cross products lose only
    // eps / sin θ. The same coordinates: ep × eb = u (ea × eb), ea × ep = v (ea × eb) in the plane.
    const Vec3 n = ea.cross(eb);
    const double nn = n.squaredNorm();
    if (!(nn > 0)) return false;
    const double u = ep.cross(eb).dot(n) / nn, v = ea.cross(ep).dot(n) / nn;
    bary = {u, v, 1 - u - v};
    return true;
  }
  const double u = (tbb * tpa - tab * tpb) / den;  // Eq. (5.56)
  const double v = (taa * tpb - tab * tpa) / den;  // Eq. (5.57)
  bary = {u, v, 1 - u - v};                        // Eq. (5.58)
  return true;
}

PhongCandidate make_candidate(const PhongTriangle& t, const Vec3& bary, double d, double tol) {
  PhongCandidate c;
  c.d = d;
  c.bary = bary;
  c.point = bary[0] * t.a + bary[1] * t.b + bary[2] * t.c;      // Eq. (5.25)
  c.normal = bary[0] * t.na + bary[1] * t.nb + bary[2] * t.nc;  // Eq. (5.26)
  c.inside = bary.minCoeff() >= -tol;
  return c;
}

}  // namespace

PhongTriangle::PhongTriangle(const Vec3& a_, const Vec3& b_, const Vec3& c_, const Vec3& na_, const Vec3& nb_,
                             const Vec3& nc_)
    : a(a_), b(b_), c(c_), na(na_), nb(nb_), nc(nc_) {
  // The plane of the shifted triangle has normal n_d = a_d×b_d + b_d×c_d + c_d×a_d and passes through
  // c_d, so Eq. (5.48) is p·n_d(d) − [a_d, b_d, c_d] = 0; expanding in d gives Eq. (5.51)–(5.54).
  r3 = -triple(na, nb, nc);                                                     // Eq. (5.51)
  k2 = na.cross(nb) + nb.cross(nc) + nc.cross(na);                              // Eq. (5.52)
  s2 = triple(a, nb, nc) + triple(b, nc, na) + triple(c, na, nb);
  k1 = a.cross(nb - nc) + b.cross(nc - na) + c.cross(na - nb);                  // Eq. (5.53)
  s1 = triple(na, b, c) + triple(nb, c, a) + triple(nc, a, b);
  k0 = a.cross(b) + b.cross(c) + c.cross(a);                                    // Eq. (5.54)
  s0 = triple(a, b, c);
}

std::array<double, 4> PhongTriangle::cubic(const Vec3& p) const {
  return {p.dot(k0) - s0, p.dot(k1) - s1, p.dot(k2) - s2, r3};
}

std::vector<PhongCandidate> phong_project_analytic(const Vec3& p, const PhongTriangle& t, double inside_tol) {
  // Work relative to the triangle's centroid: the same cubic in d (translation invariance), but the
  // coefficients no longer carry the large cancelling terms of far-from-origin coordinates.
  const Vec3 o = (t.a + t.b + t.c) / 3.0;
  const PhongTriangle local(t.a - o, t.b - o, t.c - o, t.na, t.nb, t.nc);
  const Vec3 pl = p - o;
  double roots[3];
  const int n = real_roots(local.cubic(pl), roots);
  std::vector<PhongCandidate> out;
  out.reserve(n);
  for (int i = 0; i < n; ++i) {
    Vec3 bary;
    if (!shifted_bary(pl, local, roots[i], bary)) continue;
    out.push_back(make_candidate(t, bary, roots[i], inside_tol));
  }
  std::sort(out.begin(), out.end(), [](const PhongCandidate& x, const PhongCandidate& y) {
    return std::abs(x.d) < std::abs(y.d);
  });
  return out;
}

PhongQuadratic::PhongQuadratic(const Vec3& p, const PhongTriangle& t) {
  const Vec3 ca = t.c - t.a, cb = t.c - t.b, pc = p - t.c;
  const Vec3 dna = t.na - t.nc, dnb = t.nb - t.nc;
  d0 = pc.cross(t.nc);                      // Eq. (5.30)
  du = ca.cross(t.nc) + pc.cross(dna);      // Eq. (5.31)
  dv = cb.cross(t.nc) + pc.cross(dnb);      // Eq. (5.32), with p − c (the thesis prints p − b)
  duu = ca.cross(dna);                      // Eq. (5.33)
  duv = ca.cross(dnb) + cb.cross(dna);      // Eq. (5.34)
  dvv = cb.cross(dnb);                      // Eq. (5.35)
}

Vec3 PhongQuadratic::F(double u, double v) const {
  return d0 + u * du + v * dv + u * u * duu + u * v * duv + v * v * dvv;  // Eq. (5.29)
}
Vec3 PhongQuadratic::Fu(double u, double v) const { return du + 2 * u * duu + v * duv; }  // Eq. (5.39)
Vec3 PhongQuadratic::Fv(double u, double v) const { return dv + u * duv + 2 * v * dvv; }  // Eq. (5.40)

Eigen::Vector2d PhongQuadratic::gradient(double u, double v) const {
  const Vec3 f = F(u, v);
  return 2.0 * Eigen::Vector2d(Fu(u, v).dot(f), Fv(u, v).dot(f));  // Eq. (5.37)
}

Eigen::Matrix2d PhongQuadratic::hessian(double u, double v) const {
  const Vec3 f = F(u, v), fu = Fu(u, v), fv = Fv(u, v);
  Eigen::Matrix2d H;
  // Eq. (5.38) with F_uu = 2 d_uu, F_uv = d_uv, F_vv = 2 d_vv (Eq. 5.41–5.43).
  H(0, 0) = fu.dot(fu) + 2 * duu.dot(f);
  H(0, 1) = H(1, 0) = fu.dot(fv) + duv.dot(f);
  H(1, 1) = fv.dot(fv) + 2 * dvv.dot(f);
  return 2.0 * H;
}

PhongNewtonResult phong_project_newton(const Vec3& p, const PhongTriangle& t, const PhongNewtonOptions& opt) {
  const PhongQuadratic q(p, t);
  double u = opt.start[0], v = opt.start[1];
  PhongNewtonResult res;
  for (int it = 0; it < opt.max_iterations; ++it) {
    const Eigen::Matrix2d H = q.hessian(u, v);
    const Eigen::Vector2d g = q.gradient(u, v);
    const double det = H.determinant();
    if (!(std::abs(det) > 0) || !std::isfinite(det)) break;
    const Eigen::Vector2d h = H.inverse() * (-g);  // Eq. (5.44)
    u += h[0];                                    // Eq. (5.45)
    v += h[1];
    res.iterations = it + 1;
    if (!std::isfinite(u) || !std::isfinite(v)) break;
    if (h.norm() < opt.step_tolerance) break;
  }
  const Vec3 bary(u, v, 1 - u - v);
  PhongCandidate c = make_candidate(t, bary, 0, 1e-9);
  const double nn = c.normal.squaredNorm();
  c.d = nn > 0 ? (p - c.point).dot(c.normal) / nn : 0;
  res.candidate = c;
  res.residual = std::isfinite(u) && std::isfinite(v) ? q.F(u, v).norm() : std::numeric_limits<double>::infinity();
  const double scale = std::max({(t.a - t.c).norm(), (t.b - t.c).norm(), (p - t.c).norm()}) *
                       std::max({t.na.norm(), t.nb.norm(), t.nc.norm()});
  res.converged = res.residual <= opt.residual_tolerance * std::max(scale, 1e-300);
  return res;
}

PhongProjector::PhongProjector(const Mesh& mesh, const MatrixX3d& normals, const PhongProjectionOptions& options)
    : tree_(mesh), options_(options) {
  check_options(options);
  require_valid(mesh, "Phong projection: base mesh");
  N_ = normals.rows() == 0 ? vertex_normals(mesh, NormalWeighting::Angle) : normals;
  if (N_.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
    throw InvalidInput("Phong projection: expected one normal per vertex");
  mean_edge_ = mean_edge_length(mesh);
  const MatrixX3d& V = tree_.vertices();
  const MatrixX3i& F = tree_.triangles();
  tris_.resize(F.rows());
#pragma omp parallel for schedule(static)
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int i = F(f, 0), j = F(f, 1), k = F(f, 2);
    tris_[f] = PhongTriangle(V.row(i).transpose(), V.row(j).transpose(), V.row(k).transpose(),
                             N_.row(i).transpose(), N_.row(j).transpose(), N_.row(k).transpose());
  }
  build_cones();
}

namespace {
constexpr double kAngleSlack = 1e-6;     // radians, for rounding in the roots and the cones
constexpr double kMinTolerance = 1e-6;   // the cones allow at least this barycentric tolerance
}  // namespace

// The smallest cone containing both (Shirman–Abi-Ezzi's merge of normal cones) and a sphere around both.
PhongProjector::NormalCone PhongProjector::merge(const NormalCone& x, const NormalCone& y) {
  NormalCone m;
  m.center = 0.5 * (x.center + y.center);
  m.radius = std::max((x.center - m.center).norm() + x.radius, (y.center - m.center).norm() + y.radius);
  if (x.angle >= M_PI / 2 || y.angle >= M_PI / 2) return m;
  const double phi = std::acos(std::clamp(x.axis.dot(y.axis), -1.0, 1.0));
  if (phi + y.angle <= x.angle) {
    m.axis = x.axis;
    m.angle = x.angle;
  } else if (phi + x.angle <= y.angle) {
    m.axis = y.axis;
    m.angle = y.angle;
  } else {
    const double angle = 0.5 * (phi + x.angle + y.angle);
    if (angle >= M_PI / 2 || !(std::sin(phi) > 1e-12)) return m;
    const double t = angle - x.angle;  // turn x's axis this far towards y's
    m.axis = ((std::sin(phi - t) * x.axis + std::sin(t) * y.axis) / std::sin(phi)).normalized();
    m.angle = angle + 1e-12;
  }
  return m;
}

// Can p = q + d n_q hold with q and n_q in the cone? The directions from the sphere to p lie within
// asin(radius / |p − centre|) of p − centre; one of ±them must lie within the cone's angle.
bool PhongProjector::may_project_from(const NormalCone& c, const Vec3& p) {
  if (c.angle >= M_PI / 2) return true;
  const Vec3 v = p - c.center;
  const double len = v.norm();
  if (!(len > c.radius)) return true;
  const double spread = std::asin(c.radius / len);
  const double off_axis = std::acos(std::min(1.0, std::abs(v.dot(c.axis)) / len));
  return off_axis <= c.angle + spread + kAngleSlack;
}

void PhongProjector::build_cones() {
  const MatrixX3d& V = tree_.vertices();
  const MatrixX3i& F = tree_.triangles();
  // A candidate counts as inside with barycentric coordinates w ≥ −t (Σw = 1): its normal
  // n_q = Σ w_i n_i then leaves the vertex normals' cone (half-angle β about the axis) by at most
  // tan θ = (sin β + ε) / (cos β − ε), ε = 2t max|n_i| / min|n_i| (the negative weights sum to at most
  // 2t, the positive ones to at least 1), and q lies within (1 + 4t) max|v_i − c| of the centroid c.
  const double t = std::max(options_.inside_tol, kMinTolerance);
  face_cone_.assign(F.rows(), NormalCone());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    NormalCone& c = face_cone_[f];
    Vec3 v[3], n[3];
    double lmin = std::numeric_limits<double>::infinity(), lmax = 0;
    for (int k = 0; k < 3; ++k) {
      v[k] = V.row(F(f, k)).transpose();
      n[k] = N_.row(F(f, k)).transpose();
      lmin = std::min(lmin, n[k].norm());
      lmax = std::max(lmax, n[k].norm());
    }
    c.center = (v[0] + v[1] + v[2]) / 3.0;
    for (int k = 0; k < 3; ++k) c.radius = std::max(c.radius, (v[k] - c.center).norm());
    c.radius *= 1 + 4 * t;
    if (!(lmin > 0) || !std::isfinite(lmax)) continue;
    const Vec3 sum = n[0] / n[0].norm() + n[1] / n[1].norm() + n[2] / n[2].norm();
    if (!(sum.norm() > 1e-9)) continue;
    const Vec3 axis = sum.normalized();
    double beta = 0;
    for (int k = 0; k < 3; ++k) beta = std::max(beta, std::acos(std::clamp(axis.dot(n[k]) / n[k].norm(), -1.0, 1.0)));
    const double eps = 2 * t * lmax / lmin;
    if (!(std::cos(beta) - eps > 0)) continue;
    c.axis = axis;
    c.angle = std::atan2(std::sin(beta) + eps, std::cos(beta) - eps);
  }
  // Children have larger indices than their parents: one backward sweep fills every node.
  node_cone_.assign(tree_.node_count(), NormalCone());
  for (int node = tree_.node_count() - 1; node >= 0; --node) {
    const auto [left, right] = tree_.node_children(node);
    if (left >= 0) {
      node_cone_[node] = merge(node_cone_[left], node_cone_[right]);
      continue;
    }
    const std::span<const int> fs = tree_.node_faces(node);
    NormalCone c = face_cone_[fs[0]];
    for (size_t i = 1; i < fs.size(); ++i) c = merge(c, face_cone_[fs[i]]);
    node_cone_[node] = c;
  }
}

// A root of the cubic is a projection when p − q ∥ n_q. Where the shifted triangle degenerates (radial
// normals all meet at d = −radius on a sphere) the coplanarity of Eq. (5.48) holds for any p: such a
// root is no projection (it gave d ≈ −1 for points 10^5 away from a unit sphere).
bool PhongProjector::solves(const Vec3& p, const PhongCandidate& c) const {
  const double nn = c.normal.norm();
  if (!(nn > 0)) return false;
  const Vec3 r = p - c.point;
  return r.cross(c.normal).norm() <= 1e-6 * (r.norm() + mean_edge_) * nn;
}

PhongHit PhongProjector::project(const Vec3& p) const {
  const TriangleTree::Hit closest = tree_.closest(p);
  double radius = options_.search_factor * std::sqrt(closest.sq_distance) + options_.search_margin * mean_edge_;
  // Faces nearest first: a face's Phong projection q of p satisfies p − q = d n(q) with |n| <= 1, so
  // |d| >= |p − q| >= the face's box distance; once the best |d| is below the next box distance, no
  // farther face can beat it (the search ends: linear cost even on a fan of thousands of triangles).
  PhongHit best;
  for (int attempt = 0; attempt < 5 && !best.found; ++attempt, radius *= 2) {
    double best_abs = std::numeric_limits<double>::infinity();
    tree_.visit_nearest(p, radius, [&](int f, double) {
      if (!may_project_from(face_cone_[f], p)) return std::min(radius, best_abs);
      for (const PhongCandidate& c : phong_project_analytic(p, tris_[f], options_.inside_tol)) {
        if (!c.inside || std::abs(c.d) >= best_abs || !solves(p, c)) continue;
        best_abs = std::abs(c.d);
        best.found = true;
        best.face = f;
        best.bary = c.bary;
        best.point = c.point;
        best.d = c.d;
        const double nn = c.normal.norm();
        best.normal = nn > 0 ? Vec3(c.normal / nn) : Vec3::Zero();
        best.distance = std::copysign((p - c.point).norm(), c.d);
      }
      return std::min(radius, best_abs);
    }, [&](int node) { return may_project_from(node_cone_[node], p); });
  }
  if (!best.found) {
    best.face = -1;
    best.point = closest.point;
    best.bary = closest.bary;
    const MatrixX3i& F = tree_.triangles();
    const MatrixX3d& V = tree_.vertices();
    const int f = closest.face;
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a).normalized();
    best.normal = n;
    best.distance = std::copysign(std::sqrt(closest.sq_distance), (p - closest.point).dot(n));
    best.d = best.distance;
  }
  return best;
}

std::vector<PhongHit> PhongProjector::project(const MatrixX3d& P) const {
  std::vector<PhongHit> out(P.rows());
  if (tree_.node_count() == 0) {
#pragma omp parallel for schedule(dynamic, 256)
    for (Eigen::Index i = 0; i < P.rows(); ++i) out[i] = project(Vec3(P.row(i).transpose()));
    return out;
  }
  // Along a Morton curve: nearby points share the tree's nodes in cache (same hits, in any order).
  std::vector<int> rows(P.rows());
  std::iota(rows.begin(), rows.end(), 0);
  const std::vector<int> order = morton_order(P, rows, tree_.node_box(0));
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index j = 0; j < P.rows(); ++j) out[order[j]] = project(Vec3(P.row(order[j]).transpose()));
  return out;
}

}  // namespace geotex
