// Geodesic distance by the heat method (see geodesic.h).

#include "geotex/toolkit/geodesic.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <limits>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

const OptionTable<HeatGeodesicOptions>& HeatGeodesicOptions::table() {
  using O = HeatGeodesicOptions;
  static const auto t = OptionTable<O>().add(
      "heat_time", &O::time_factor, "heat method: diffusion time in squared mean edge lengths", positive(),
      "Crane et al. 2013");
  return t;
}

struct HeatGeodesics::Impl {
  MatrixX3i F;
  MatrixX3d X;
  // Per face: the rotated opposite edges n_f × e_i / (2 A_f) (∇ of the hat functions, Eq. 5.72) and
  // half the cotangents of the corners, for the divergence.
  std::vector<std::array<Vec3, 3>> grad;
  std::vector<std::array<double, 3>> half_cot;
  SpdSolver heat, poisson;
  Eigen::VectorXi component;
  std::vector<int> roots;  // one vertex per component, where φ is pinned to 0
  Eigen::VectorXd mass;    // lumped masses (isolated vertices: the mean), to balance the Poisson sources
  int n = 0;
};

HeatGeodesics::HeatGeodesics(const Mesh& mesh, const HeatGeodesicOptions& options) : impl_(std::make_unique<Impl>()) {
  require_valid(mesh, "geodesic distance: mesh");
  HeatGeodesicOptions::table().check(options);
  Impl& m = *impl_;
  m.n = static_cast<int>(mesh.n_vertices());
  m.F = faces(mesh);
  m.X = positions(mesh);
  m.component = connected_components(mesh);
  const Eigen::Index nf = m.F.rows();
  m.grad.resize(nf);
  m.half_cot.resize(nf);
  const CotanOptions co;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Vec3 p[3] = {m.X.row(m.F(f, 0)), m.X.row(m.F(f, 1)), m.X.row(m.F(f, 2))};
    const Vec3 cr = (p[1] - p[0]).cross(p[2] - p[0]);
    const double l2 = std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm()});
    const double area2 = std::max(cr.norm(), l2 / co.max_cot);  // the same floor as cotan_matrix()
    const Vec3 nrm = cr.norm() > 0 ? Vec3(cr.normalized()) : Vec3::Zero();
    for (int i = 0; i < 3; ++i) {
      const Vec3& a = p[(i + 1) % 3];
      const Vec3& b = p[(i + 2) % 3];
      m.grad[f][i] = nrm.cross(b - a) / area2;  // ∇φ_i: the opposite edge turned inwards, over 2A
      const Vec3 u = a - p[i], v = b - p[i];
      m.half_cot[f][i] = 0.5 * std::clamp(u.dot(v) / area2, -co.max_cot, co.max_cot);
    }
  }
  const SparseMatrix C = cotan_matrix(mesh, co);
  Eigen::VectorXd M = mass_diagonal(mesh, MassType::Voronoi);
  // An isolated vertex has no mass and no cotangent row: give it the mean mass, so that both systems
  // stay definite; it is its own component, never reached (+∞).
  const double mean_mass = M.sum() / std::max<Eigen::Index>(1, (M.array() > 0).count());
  for (Eigen::Index i = 0; i < M.size(); ++i)
    if (!(M[i] > 0)) M[i] = mean_mass;
  const double t = options.time_factor * std::pow(mean_edge_length(mesh), 2);
  const SparseMatrix H = SparseMatrix(M.asDiagonal()) - t * C;
  m.heat.compute(H);
  m.mass = M;
  // −C is singular (a constant per component): pin φ = 0 at one vertex of each component and drop its
  // equation, which the others imply once the sources balance (distance()). A vanishing multiple of M
  // instead left pivots below round-off on components of needle triangles (|cot| at its cap).
  std::vector<char> is_root(m.n, 0);
  std::vector<char> seen(m.component.size() ? m.component.maxCoeff() + 1 : 0, 0);
  for (int i = 0; i < m.n; ++i)
    if (!seen[m.component[i]]) {
      seen[m.component[i]] = 1;
      is_root[i] = 1;
      m.roots.push_back(i);
    }
  // A needle triangle (collinear corners, cotangents at their cap) has a second near-null direction,
  // a zero-area triangle a vertex without any weight: 1e-12 of each diagonal plus of the mean one keeps
  // those pivots above round-off and moves φ by about 1e-12 × #V relatively.
  SparseMatrix P = -C;
  const double unit = std::max(1e-300, (-C.diagonal()).cwiseAbs().mean());
  for (Eigen::Index k = 0; k < P.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(P, k); it; ++it)
      if (is_root[it.row()] || is_root[it.col()]) it.valueRef() = it.row() == it.col() ? unit : 0.0;
      else if (it.row() == it.col()) it.valueRef() += 1e-12 * (std::abs(it.value()) + unit);
  for (int r : m.roots) P.coeffRef(r, r) = unit;  // isolated vertices have no entry yet
  m.poisson.compute(P);
}

HeatGeodesics::~HeatGeodesics() = default;
HeatGeodesics::HeatGeodesics(HeatGeodesics&&) noexcept = default;
HeatGeodesics& HeatGeodesics::operator=(HeatGeodesics&&) noexcept = default;

Eigen::VectorXd HeatGeodesics::distance(const std::vector<int>& sources) const {
  const Impl& m = *impl_;
  if (sources.empty()) throw InvalidInput("geodesic distance: no source vertex");
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(m.n);
  for (int s : sources) {
    if (s < 0 || s >= m.n)
      throw InvalidInput("geodesic distance: source vertex " + std::to_string(s) + " out of range [0, " +
                         std::to_string(m.n) + ")");
    delta[s] = 1;
  }
  const Eigen::VectorXd u = m.heat.solve(delta);
  // Divergence of the normalised, reversed gradient (integrated over each vertex's dual cell).
  Eigen::VectorXd div = Eigen::VectorXd::Zero(m.n);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    Vec3 g = Vec3::Zero();
    for (int i = 0; i < 3; ++i) g += u[m.F(f, i)] * m.grad[f][i];
    const double len = g.norm();
    if (!(len > 0)) continue;
    const Vec3 Xf = -g / len;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const Vec3 xi = m.X.row(m.F(f, i)), xj = m.X.row(m.F(f, j)), xk = m.X.row(m.F(f, k));
      // cot of the angle at k faces the edge i→j; cot at j faces i→k.
      div[m.F(f, i)] += m.half_cot[f][k] * (xj - xi).dot(Xf) + m.half_cot[f][j] * (xk - xi).dot(Xf);
    }
  }
  // C φ = div needs Σ div = 0 over each component; on an open surface the boundary flux is left over.
  // Spread it in proportion to the masses (what (εM − C) φ = −div does as ε → 0), then solve with
  // φ = 0 at each component's root.
  const int ncomp = m.component.size() ? m.component.maxCoeff() + 1 : 0;
  std::vector<double> flux(ncomp, 0.0), mass(ncomp, 0.0);
  for (int i = 0; i < m.n; ++i) {
    flux[m.component[i]] += div[i];
    mass[m.component[i]] += m.mass[i];
  }
  for (int i = 0; i < m.n; ++i) div[i] -= m.mass[i] * flux[m.component[i]] / mass[m.component[i]];
  for (int r : m.roots) div[r] = 0;
  Eigen::VectorXd phi = m.poisson.solve(-div);
  // Shift each source's component so that its sources sit at 0; unreached components are at +∞.
  const int nc = m.component.size() ? m.component.maxCoeff() + 1 : 0;
  std::vector<double> shift(nc, std::numeric_limits<double>::infinity());
  for (int s : sources) shift[m.component[s]] = std::min(shift[m.component[s]], phi[s]);
  for (int i = 0; i < m.n; ++i) {
    const double sh = shift[m.component[i]];
    phi[i] = std::isfinite(sh) ? std::max(0.0, phi[i] - sh) : std::numeric_limits<double>::infinity();
  }
  return phi;
}

Eigen::VectorXd heat_geodesic_distance(const Mesh& mesh, const std::vector<int>& sources,
                                       const HeatGeodesicOptions& options) {
  return HeatGeodesics(mesh, options).distance(sources);
}

}  // namespace geotex
