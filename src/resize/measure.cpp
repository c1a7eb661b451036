#include "geotex/resize/measure.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {

namespace {

// Each vertex's share of the surface: a third of its triangles' areas.
Eigen::VectorXd vertex_shares(const Mesh& mesh) {
  const Eigen::VectorXd fa = face_areas(mesh);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(mesh.n_vertices());
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) a[v.idx()] += fa[f.idx()] / 3.0;
  return a;
}

}  // namespace

BumpShape measure_bump(const MatrixX3d& X0, const MatrixX3d& X1, const Vec3& centre, double radius) {
  std::vector<int> rim;
  int tip = -1;
  double best = 1e300;
  for (Eigen::Index i = 0; i < X0.rows(); ++i) {
    const double r = (X0.row(i).head<2>() - centre.head<2>().transpose()).norm();
    if (r >= 0.7 * radius && r <= 0.95 * radius) rim.push_back(static_cast<int>(i));
    if (r < best) { best = r; tip = static_cast<int>(i); }
  }
  if (rim.size() < 3 || tip < 0) throw InvalidInput("measure_bump: too few vertices in the bump's rim ring");
  Eigen::MatrixX3d P(rim.size(), 3);
  for (size_t k = 0; k < rim.size(); ++k) P.row(k) = X1.row(rim[k]);
  const Eigen::RowVector3d c = P.colwise().mean();
  const Eigen::MatrixX3d Pc = P.rowwise() - c;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Pc.transpose() * Pc / static_cast<double>(rim.size()));
  // eigenvalues ascending: [0] is the plane normal's, [1], [2] the in-plane spreads.
  Vec3 nrm = es.eigenvectors().col(0);
  const Vec3 up = X1.row(tip).transpose() - c.transpose();
  if (nrm.dot(up) < 0) nrm = -nrm;
  BumpShape s;
  s.aspect = std::sqrt(es.eigenvalues()[2] / es.eigenvalues()[1]);
  s.height = nrm.dot(up);
  s.tilt_deg = std::acos(std::clamp(nrm.dot(up.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
  return s;
}

ProtrusionPose measure_protrusion(const Mesh& mesh, const MatrixX3d& X, int tip, const Eigen::VectorXd& footprint) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (X.rows() != n || footprint.size() != n || tip < 0 || tip >= n)
    throw InvalidInput("measure_protrusion: positions, footprint and tip must match the mesh");
  std::vector<char> ring(n, 0);
  for (auto e : mesh.edges()) {
    const int a = e.v0().idx(), b = e.v1().idx();
    if ((footprint[a] > 0.5) != (footprint[b] > 0.5)) ring[footprint[a] > 0.5 ? b : a] = 1;
  }
  std::vector<int> R;
  for (int i = 0; i < n; ++i)
    if (ring[i]) R.push_back(i);
  if (R.size() < 3) throw InvalidInput("measure_protrusion: the foot ring has fewer than 3 vertices");
  Mesh m = mesh;
  set_positions(m, X);
  const MatrixX3d N = vertex_normals(m);
  Eigen::MatrixX3d P(R.size(), 3);
  Vec3 nsum = Vec3::Zero();
  for (size_t k = 0; k < R.size(); ++k) {
    P.row(k) = X.row(R[k]);
    nsum += N.row(R[k]).transpose();
  }
  const Eigen::RowVector3d c = P.colwise().mean();
  const Eigen::MatrixX3d Pc = P.rowwise() - c;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Pc.transpose() * Pc);
  Vec3 nrm = es.eigenvectors().col(0);
  if (nrm.dot(nsum) < 0) nrm = -nrm;
  const Vec3 d = X.row(tip).transpose() - c.transpose();
  ProtrusionPose p;
  p.length = d.norm();
  p.angle_deg = p.length > 0 ? std::acos(std::clamp(nrm.dot(d) / p.length, -1.0, 1.0)) * 180.0 / M_PI : 0.0;
  return p;
}

std::vector<RegionExtents> region_extents(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (X.rows() != n || f.size() != n) throw InvalidInput("region_extents: positions and weights must match the mesh");
  const Eigen::VectorXd area = vertex_shares(mesh);
  std::vector<int> region(n, -1), stack;
  std::vector<RegionExtents> out;
  for (int seed = 0; seed < n; ++seed) {
    if (!(f[seed] > 0.5) || region[seed] >= 0) continue;
    RegionExtents r;
    region[seed] = static_cast<int>(out.size());
    stack.assign(1, seed);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      r.vertices.push_back(v);
      for (auto w : mesh.vv_range(mesh.vertex_handle(v)))
        if (f[w.idx()] > 0.5 && region[w.idx()] < 0) {
          region[w.idx()] = region[seed];
          stack.push_back(w.idx());
        }
    }
    double wsum = 0;
    Vec3 mean = Vec3::Zero();
    for (int v : r.vertices) {
      wsum += area[v];
      mean += area[v] * X.row(v).transpose();
    }
    if (wsum > 0) {
      mean /= wsum;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (int v : r.vertices) {
        const Vec3 d = X.row(v).transpose() - mean;
        cov += area[v] * d * d.transpose();
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov / wsum);
      const Vec3 ev = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
      r.extents = Vec3(ev[2], ev[1], ev[0]);
    }
    out.push_back(std::move(r));
  }
  return out;
}

double aspect_change(const Vec3& a, const Vec3& b) {
  if (!(a[0] > 0) || !(b[0] > 0)) return 0;
  double worst = 0;
  for (int k = 1; k < 3; ++k) {
    const double ra = a[k] / a[0], rb = b[k] / b[0];
    if (ra > 1e-12) worst = std::max(worst, std::abs(rb / ra - 1));
  }
  return worst;
}

double rim_crease_deg(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f, int rings, double q) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (X.rows() != n || f.size() != n) throw InvalidInput("rim_crease_deg: positions and weights must match the mesh");
  Mesh m = mesh;
  set_positions(m, X);
  const Eigen::VectorXd theta = dihedral_angles(m);
  Eigen::VectorXd band = Eigen::VectorXd::Zero(n);
  for (auto e : m.edges()) {
    const int a = e.v0().idx(), b = e.v1().idx();
    if ((f[a] > 0.5) != (f[b] > 0.5)) band[a] = band[b] = 1;
  }
  for (int r = 0; r < rings; ++r) {
    Eigen::VectorXd next = band;
    for (auto e : m.edges()) {
      const int a = e.v0().idx(), b = e.v1().idx();
      next[a] = std::max(next[a], band[b]);
      next[b] = std::max(next[b], band[a]);
    }
    band = next;
  }
  std::vector<double> angles;
  for (auto e : m.edges())
    if (band[e.v0().idx()] > 0 && band[e.v1().idx()] > 0) angles.push_back(std::abs(theta[e.idx()]) * 180.0 / M_PI);
  if (angles.empty()) return 0;
  const size_t k = std::min(angles.size() - 1, static_cast<size_t>(std::clamp(q, 0.0, 1.0) * (angles.size() - 1)));
  std::nth_element(angles.begin(), angles.begin() + k, angles.end());
  return angles[k];
}

}  // namespace geotex
