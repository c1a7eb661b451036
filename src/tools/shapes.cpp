#include "geotex/tools/shapes.h"

#include <array>
#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"

namespace geotex {

namespace {
Mesh from_lists(const std::vector<Vec3>& V, const std::vector<std::array<int, 3>>& F) {
  MatrixX3d Vm(V.size(), 3);
  for (size_t i = 0; i < V.size(); ++i) Vm.row(i) = V[i].transpose();
  MatrixX3i Fm(F.size(), 3);
  for (size_t i = 0; i < F.size(); ++i) Fm.row(i) << F[i][0], F[i][1], F[i][2];
  return make_mesh(Vm, Fm);
}
}  // namespace

Mesh subdivided_cube(int n, double size) {
  if (n < 1) throw InvalidInput("cube: n must be >= 1");
  std::vector<Vec3> V;
  std::vector<std::array<int, 3>> F;
  std::unordered_map<int64_t, int> index;  // lattice point (i, j, k) -> vertex
  auto vid = [&](int i, int j, int k) {
    const int64_t key = (int64_t(i) * (n + 1) + j) * (n + 1) + k;
    auto [it, inserted] = index.emplace(key, static_cast<int>(V.size()));
    if (inserted) V.push_back(size * (Vec3(i, j, k) / n - Vec3::Constant(0.5)));
    return it->second;
  };
  // Each face: fixed axis a at value s (0 or n), spanned by axes u, v with u × v along the outward normal.
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      int u = (a + 1) % 3, v = (a + 2) % 3;
      if (side == 0) std::swap(u, v);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          int q[4];
          const int corner[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int c = 0; c < 4; ++c) {
            int p[3];
            p[a] = side * n;
            p[u] = corner[c][0];
            p[v] = corner[c][1];
            q[c] = vid(p[0], p[1], p[2]);
          }
          // Alternate the diagonal so the mesh has no directional bias.
          if ((i + j) % 2 == 0) {
            F.push_back({q[0], q[1], q[2]});
            F.push_back({q[0], q[2], q[3]});
          } else {
            F.push_back({q[0], q[1], q[3]});
            F.push_back({q[1], q[2], q[3]});
          }
        }
    }
  return from_lists(V, F);
}

Mesh cylinder(double radius, double height, int segments, int rings) {
  if (segments < 3 || rings < 1) throw InvalidInput("cylinder: needs segments >= 3 and rings >= 1");
  std::vector<Vec3> V;
  std::vector<std::array<int, 3>> F;
  const int s = segments;
  // Side: rings+1 circles of s vertices.
  for (int r = 0; r <= rings; ++r)
    for (int k = 0; k < s; ++k) {
      const double t = 2 * M_PI * k / s;
      V.emplace_back(radius * std::cos(t), radius * std::sin(t), height * (double(r) / rings - 0.5));
    }
  auto side = [&](int r, int k) { return r * s + (k % s); };
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < s; ++k) {
      F.push_back({side(r, k), side(r, k + 1), side(r + 1, k + 1)});
      F.push_back({side(r, k), side(r + 1, k + 1), side(r + 1, k)});
    }
  // Caps: concentric circles whose vertex counts shrink towards the centre.
  const double edge = 2 * M_PI * radius / s;
  const int n_circles = std::max(1, static_cast<int>(std::round(radius / edge)));
  for (int cap = 0; cap < 2; ++cap) {
    const double z = cap == 0 ? -0.5 * height : 0.5 * height;
    std::vector<int> outer(s);
    for (int k = 0; k < s; ++k) outer[k] = cap == 0 ? side(0, k) : side(rings, k);
    for (int c = n_circles - 1; c >= 0; --c) {
      std::vector<int> inner;
      const double rad = radius * c / n_circles;
      const int m = c == 0 ? 1 : std::max(3, static_cast<int>(std::round(s * double(c) / n_circles)));
      for (int k = 0; k < m; ++k) {
        const double t = 2 * M_PI * (k + 0.5 * (c % 2)) / m;
        inner.push_back(static_cast<int>(V.size()));
        V.emplace_back(rad * std::cos(t), rad * std::sin(t), z);
      }
      // Stitch outer (size a) and inner (size b) rings by marching on angle.
      const int a = static_cast<int>(outer.size()), b = static_cast<int>(inner.size());
      int i = 0, j = 0;
      while (i < a || j < b) {
        const double ta = (i + 0.5) / a, tb = (j + 0.5) / b;
        const bool advance_outer = j >= b || (i < a && ta <= tb);
        std::array<int, 3> tri;
        if (advance_outer) {
          tri = {outer[i % a], outer[(i + 1) % a], inner[j % b]};
          ++i;
        } else {
          tri = {outer[i % a], inner[(j + 1) % b], inner[j % b]};
          ++j;
        }
        if (b == 1 && !advance_outer) continue;
        if (cap == 0) std::swap(tri[1], tri[2]);  // bottom cap faces -z
        F.push_back(tri);
      }
      outer = inner;
    }
  }
  return from_lists(V, F);
}

Mesh icosphere(int subdivisions, double radius) {
  if (subdivisions < 0 || subdivisions > 10) throw InvalidInput("icosphere: subdivisions must be in [0, 10]");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> V = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> F = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                       {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& v : V) v.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      V.push_back((V[a] + V[b]).normalized());
      return mid[key] = static_cast<int>(V.size()) - 1;
    };
    std::vector<std::array<int, 3>> G;
    G.reserve(4 * F.size());
    for (auto& f : F) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      G.push_back({f[0], a, c});
      G.push_back({f[1], b, a});
      G.push_back({f[2], c, b});
      G.push_back({a, b, c});
    }
    F.swap(G);
  }
  for (auto& v : V) v *= radius;
  return from_lists(V, F);
}

Mesh torus(double R, double r, int nu, int nv) {
  if (nu < 3 || nv < 3) throw InvalidInput("torus: needs nu, nv >= 3");
  std::vector<Vec3> V;
  std::vector<std::array<int, 3>> F;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      V.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return from_lists(V, F);
}

Mesh plane(int n, double size) {
  if (n < 1) throw InvalidInput("plane: n must be >= 1");
  std::vector<Vec3> V;
  std::vector<std::array<int, 3>> F;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) V.emplace_back(size * (double(i) / n - 0.5), size * (double(j) / n - 0.5), 0.0);
  auto id = [&](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if ((i + j) % 2 == 0) {
        F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        F.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        F.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return from_lists(V, F);
}

namespace {
// A ring of vertices around the x axis: indices and the angular offset of vertex 0 (fraction of a step).
struct Ring {
  std::vector<int> v;
  double offset = 0;
};

// Triangles between ring a and ring b (b at larger x), outward for rings ordered by increasing angle
// about +x: march around both rings, always advancing the one whose next edge midpoint comes first.
void stitch(const Ring& a, const Ring& b, std::vector<std::array<int, 3>>& F) {
  const int na = static_cast<int>(a.v.size()), nb = static_cast<int>(b.v.size());
  int i = 0, j = 0;
  while (i < na || j < nb) {
    const double ta = (i + 0.5 + a.offset) / na, tb = (j + 0.5 + b.offset) / nb;
    const bool advance_a = nb == 1 ? true : na == 1 ? false : (j >= nb || (i < na && ta <= tb));
    if (advance_a) {
      if (na > 1) F.push_back({a.v[i % na], a.v[(i + 1) % na], b.v[j % nb]});
      ++i;
    } else {
      if (nb > 1) F.push_back({a.v[i % na], b.v[(j + 1) % nb], b.v[j % nb]});
      ++j;
    }
    if (na == 1 && j >= nb) break;
    if (nb == 1 && i >= na) break;
  }
}
}  // namespace

Mesh capsule(double radius, double length, int segments) {
  if (!(radius > 0) || !(length >= 0) || segments < 6) throw InvalidInput("capsule: needs radius > 0, length >= 0, segments >= 6");
  const double edge = 2 * M_PI * radius / segments, spacing = edge * std::sqrt(3.0) / 2;
  const int n_cyl = std::max(1, static_cast<int>(std::round(length / spacing)));
  const int n_cap = std::max(2, static_cast<int>(std::round(0.5 * M_PI * radius / spacing)));
  std::vector<Vec3> V;
  std::vector<std::array<int, 3>> F;
  auto make_ring = [&](double x, double r, int m, double offset) {
    Ring ring;
    ring.offset = offset;
    for (int k = 0; k < m; ++k) {
      const double psi = 2 * M_PI * (k + offset) / m;
      ring.v.push_back(static_cast<int>(V.size()));
      V.emplace_back(x, r * std::cos(psi), r * std::sin(psi));
    }
    return ring;
  };
  // Rings from the pole at −x to the pole at +x; cap latitude rings shrink with cos(latitude).
  std::vector<Ring> rings;
  for (int k = n_cap; k >= 1; --k) {
    const double phi = 0.5 * M_PI * k / n_cap;
    const int m = k == n_cap ? 1 : std::max(6, static_cast<int>(std::round(segments * std::cos(phi))));
    rings.push_back(make_ring(-0.5 * length - radius * std::sin(phi), radius * std::cos(phi), m, 0.5 * (k % 2)));
  }
  for (int k = 0; k <= n_cyl; ++k)
    rings.push_back(make_ring(length * (double(k) / n_cyl - 0.5), radius, segments, 0.5 * ((n_cap + k) % 2)));
  for (int k = 1; k <= n_cap; ++k) {
    const double phi = 0.5 * M_PI * k / n_cap;
    const int m = k == n_cap ? 1 : std::max(6, static_cast<int>(std::round(segments * std::cos(phi))));
    rings.push_back(make_ring(0.5 * length + radius * std::sin(phi), radius * std::cos(phi), m, 0.5 * ((n_cap + n_cyl + k) % 2)));
  }
  for (size_t k = 0; k + 1 < rings.size(); ++k) stitch(rings[k], rings[k + 1], F);
  return from_lists(V, F);
}

TexturedShape tentacles(const Mesh& base, const TentacleOptions& o, std::vector<int> feet, std::vector<Vec3> leans,
                        std::vector<double> bend_deg, std::vector<Tentacle>* info) {
  require_valid(base, "tentacles: base mesh");
  if (!(o.radius > 0) || !(o.length > 0) || !(o.thickness > 0) || o.thickness >= o.radius || !(o.foot > 0 && o.foot < 1))
    throw InvalidInput("tentacles: needs 0 < thickness < radius, length > 0 and foot in (0, 1)");
  const double R = o.radius, L = o.length, rho = o.thickness;
  const MatrixX3d X = positions(base);
  const MatrixX3d N = vertex_normals(base, NormalWeighting::Area);
  const int n = static_cast<int>(base.n_vertices());
  Rng rng(o.seed);
  if (feet.empty()) {  // random interior vertices, footprints well apart and away from the boundary
    std::vector<char> near_boundary(n, 0);
    for (auto v : base.vertices())
      if (base.is_boundary(v))
        for (int w = 0; w < n; ++w)
          if ((X.row(w) - X.row(v.idx())).norm() < 1.5 * R) near_boundary[w] = 1;
    for (int attempt = 0; attempt < 200 * o.count && static_cast<int>(feet.size()) < o.count; ++attempt) {
      const int c = static_cast<int>(rng.below(n));
      if (near_boundary[c] || base.is_isolated(base.vertex_handle(c))) continue;
      bool ok = true;
      for (int f : feet) ok = ok && (X.row(f) - X.row(c)).norm() >= 3 * R;
      if (ok) feet.push_back(c);
    }
  }
  for (int f : feet)
    if (f < 0 || f >= n) throw InvalidInput(fmt::format("tentacles: foot vertex {} out of range", f));
  while (leans.size() < feet.size()) leans.emplace_back(rng.normal(), rng.normal(), rng.normal());
  while (bend_deg.size() < feet.size()) bend_deg.push_back(40 + 40 * rng.uniform());

  TexturedShape out;
  out.base = base;
  out.textured = base;
  MatrixX3d Y = X;
  std::vector<Tentacle> made;
  for (size_t k = 0; k < feet.size(); ++k) {
    const int c = feet[k];
    const Vec3 xc = X.row(c), nc = N.row(c).normalized();
    Vec3 l = leans[k] - leans[k].dot(nc) * nc;
    l = l.norm() > 1e-9 ? Vec3(l.normalized()) : nc.unitOrthogonal();
    const Vec3 b = nc.cross(l);
    const double kappa = bend_deg[k] * M_PI / 180.0 / L;  // the centreline turns at a constant rate
    for (int i = 0; i < n; ++i) {
      const Vec3 d = X.row(i).transpose() - xc;
      const double r = d.norm();
      if (r >= R) continue;
      const double t = 1.0 - r / R;  // 0 at the rim, 1 at the centre
      double s, radius;
      if (t < o.foot) {  // the foot: rises by one shaft radius while narrowing to the shaft
        const double u = t / o.foot;
        s = rho * u * u;
        radius = rho + (R - rho) * (1 - u) * (1 - u);
      } else {  // the shaft, slightly tapered, with a rounded tip
        const double v = (t - o.foot) / (1 - o.foot);
        s = rho + (L - rho) * v;
        radius = rho * (1 - 0.35 * v);
        const double w = (s - (L - radius)) / radius;
        if (w > 0) radius *= std::sqrt(std::max(0.0, 1 - w * w));
      }
      const double theta = kappa * s;
      const Vec3 C = kappa > 1e-12 ? Vec3(xc + nc * std::sin(theta) / kappa + l * (1 - std::cos(theta)) / kappa)
                                   : Vec3(xc + nc * s);
      const Vec3 across = std::cos(theta) * l - std::sin(theta) * nc;  // the centreline's normal in the lean plane
      const Vec3 dt = d - d.dot(nc) * nc;
      const double psi = dt.norm() > 1e-12 * R ? std::atan2(dt.dot(b), dt.dot(l)) : 0.0;
      const Vec3 now = C + radius * (std::cos(psi) * across + std::sin(psi) * b);
      const Vec3 flat = xc + r * (std::cos(psi) * l + std::sin(psi) * b);
      Y.row(i) += (now - flat).transpose();
    }
    out.spike_centres.push_back(c);
    out.lean.push_back(l);
    Tentacle tk;
    tk.foot = c;
    tk.lean = l;
    tk.bend_deg = bend_deg[k];
    const Vec3 tip = Y.row(c).transpose() - xc;
    tk.length = tip.norm();
    tk.lean_deg = std::acos(std::clamp(tip.normalized().dot(nc), -1.0, 1.0)) * 180.0 / M_PI;
    made.push_back(tk);
  }
  set_positions(out.textured, Y);
  if (info) *info = made;
  return out;
}

namespace {
int nearest_vertex(const MatrixX3d& X, const Vec3& p) {
  Eigen::Index best;
  (X.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}
}  // namespace

TexturedShape tentacle_stick(int level, std::vector<Tentacle>* info) {
  if (level < 0 || level > 4) throw InvalidInput("tentacle stick: level must be in [0, 4]");
  const Mesh base = capsule(1.0, 6.0, 80 << level);
  const MatrixX3d X = positions(base);
  std::vector<int> feet;
  std::vector<Vec3> leans;
  std::vector<double> bend;
  for (int k = 0; k < 9; ++k) {
    const double x = -2.4 + 4.8 * k / 8, psi = 2.39996 * k;  // a spiral at the golden angle
    feet.push_back(nearest_vertex(X, Vec3(x, std::cos(psi), std::sin(psi))));
    const double a = k * 75.0 * M_PI / 180.0;                 // along the axis, around it, and between
    leans.push_back(std::cos(a) * Vec3::UnitX() + std::sin(a) * Vec3(0, -std::sin(psi), std::cos(psi)));
    bend.push_back(45.0 + 30.0 * ((5 * k) % 9) / 8.0);
  }
  return tentacles(base, {}, feet, leans, bend, info);
}

TexturedShape tentacle_plane(int level, std::vector<Tentacle>* info) {
  if (level < 0 || level > 4) throw InvalidInput("tentacle plane: level must be in [0, 4]");
  const Mesh base = plane(64 << level, 4.0);
  const MatrixX3d X = positions(base);
  std::vector<int> feet;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) feet.push_back(nearest_vertex(X, Vec3(1.2 * i, 1.2 * j, 0)));
  TentacleOptions o;
  o.length = 1.0;
  return tentacles(base, o, feet, std::vector<Vec3>(feet.size(), Vec3::UnitX()), std::vector<double>(feet.size(), 60.0),
                   info);
}

Eigen::VectorXd tentacle_truth(const Mesh& base, const std::vector<Tentacle>& tentacles, double radius) {
  const MatrixX3d X = positions(base);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(X.rows());
  for (const auto& t : tentacles)
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if ((X.row(i) - X.row(t.foot)).norm() < radius) f[i] = 1;
  return f;
}

TexturedShape spiky(const Mesh& base, const SpikeOptions& opt) {
  require_valid(base, "spiky: base mesh");
  TexturedShape out;
  out.base = base;
  out.textured = base;
  const double h = mean_edge_length(base);
  const double R = opt.radius * h, H = opt.height * h;
  const double lean = opt.lean_deg * M_PI / 180.0;
  const MatrixX3d X = positions(base);
  const MatrixX3d N = vertex_normals(base, NormalWeighting::Area);
  Rng rng(opt.seed);

  // Spike centres: random interior vertices at least 2.5 footprints apart.
  std::vector<char> near_boundary(base.n_vertices(), 0);
  for (auto v : base.vertices())
    if (base.is_boundary(v))
      for (auto w : base.vertices())
        if ((X.row(w.idx()) - X.row(v.idx())).norm() < 1.5 * R) near_boundary[w.idx()] = 1;
  const int n = static_cast<int>(base.n_vertices());
  for (int attempt = 0; attempt < 200 * opt.count && static_cast<int>(out.spike_centres.size()) < opt.count; ++attempt) {
    const int c = static_cast<int>(rng.below(n));
    if (near_boundary[c] || base.is_isolated(base.vertex_handle(c))) continue;
    bool ok = true;
    for (int o : out.spike_centres)
      if ((X.row(o) - X.row(c)).norm() < 2.5 * R) ok = false;
    if (!ok) continue;
    out.spike_centres.push_back(c);
    const Vec3 nc = N.row(c);
    Vec3 dir = opt.random_lean ? Vec3(rng.normal(), rng.normal(), rng.normal()) : Vec3(1, 0, 0);
    dir -= dir.dot(nc) * nc;
    if (dir.norm() < 1e-6) dir = nc.unitOrthogonal();
    out.lean.push_back(dir.normalized());
  }

  MatrixX3d Y = X;
  for (size_t s = 0; s < out.spike_centres.size(); ++s) {
    const int c = out.spike_centres[s];
    for (int i = 0; i < n; ++i) {
      const double r = (X.row(i) - X.row(c)).norm();
      if (r >= R) continue;
      const double t = 1.0 - r / R;         // 1 at the tip, 0 at the rim
      const double height = H * t * t;      // pointed profile
      const double theta = lean * t * t;    // the spike bends more towards its tip
      const Vec3 n_i = N.row(i);
      Vec3 t_i = out.lean[s] - out.lean[s].dot(n_i) * n_i;
      t_i = t_i.norm() > 1e-9 ? Vec3(t_i.normalized()) : n_i.unitOrthogonal();
      Y.row(i) += height * (std::cos(theta) * n_i + std::sin(theta) * t_i).transpose();
    }
  }
  set_positions(out.textured, Y);
  return out;
}

std::vector<std::string> shape_names() {
  return {"cube", "cylinder", "sphere", "torus", "plane", "capsule", "spiky-sphere", "spiky-plane", "tentacle-stick",
          "tentacle-plane", "bumpy-plate", "ridge-plate"};
}

TexturedShape make_shape(const std::string& name, int level, uint64_t seed) {
  if (level < 0 || level > 8) throw InvalidInput("shape level must be in [0, 8]");
  const int k = 1 << level;
  TexturedShape s;
  if (name == "cube") s.base = subdivided_cube(5 * k);
  else if (name == "cylinder") s.base = cylinder(0.5, 1.0, 24 * k, 12 * k);
  else if (name == "sphere") s.base = icosphere(3 + level);
  else if (name == "torus") s.base = torus(1.0, 0.35, 32 * k, 12 * k);
  else if (name == "plane") s.base = plane(20 * k);
  else if (name == "capsule") s.base = capsule(1.0, 6.0, 40 * k);
  else if (name == "tentacle-stick") return tentacle_stick(level);
  else if (name == "tentacle-plane") return tentacle_plane(level);
  else if (name == "bumpy-plate" || name == "ridge-plate") {  // feature-aware resizing's plates (resize/measure.h)
    const int n = std::min(40 * k, 4000);
    const BumpyPlate b = name == "bumpy-plate" ? bumpy_plate({.n = n}) : ridge_plate(n);
    s.base = plane(n, 2.0);
    s.textured = b.mesh;
    const MatrixX3d X = positions(s.base);
    for (const Vec3& c : b.centres) s.spike_centres.push_back(nearest_vertex(X, c));
    return s;
  }
  else if (name == "spiky-sphere" || name == "spiky-plane") {
    SpikeOptions o;
    o.seed = seed;
    if (name == "spiky-sphere") {
      o.count = 12 * k;
      return spiky(icosphere(3 + level), o);
    }
    o.count = 4 * k * k;
    return spiky(plane(20 * k), o);
  } else {
    throw InvalidInput(fmt::format("unknown shape '{}' (choose from: {})", name, fmt::join(shape_names(), ", ")));
  }
  s.textured = s.base;
  return s;
}

namespace {
// Distance in the xy-plane from p to the segment [a, b].
double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  const double s = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + s * d)).norm();
}

}  // namespace

BumpyPlate bumpy_plate(const BumpyPlateOptions& o) {
  if (o.n < 2 || o.bumps < 0 || !(o.radius > 0) || !(o.ridge_length >= 0)) throw InvalidInput("bumpy_plate: bad options");
  BumpyPlate b;
  b.mesh = plane(o.n, 2.0);
  b.radius = o.radius;
  b.height = o.height;
  for (int i = 0; i < o.bumps; ++i)
    for (int j = 0; j < o.bumps; ++j)
      b.centres.emplace_back((i - 0.5 * (o.bumps - 1)) * o.spacing, (j - 0.5 * (o.bumps - 1)) * o.spacing, 0.0);
  const Eigen::Vector2d r0(0, -0.5 * o.ridge_length), r1(0, 0.5 * o.ridge_length);
  if (o.ridge_length > 0)
    for (const Vec3& c : b.centres)
      if (segment_distance(c.head<2>(), r0, r1) < 2 * o.radius) throw InvalidInput("bumpy_plate: the ridge overlaps a bump");
  MatrixX3d X = positions(b.mesh);
  b.truth = Eigen::VectorXd::Zero(X.rows());
  b.ridge = Eigen::VectorXd::Zero(X.rows());
  auto profile = [&](double r) {  // h (1 − r²/R²)², C¹ at the rim
    const double s = 1.0 - r * r / (o.radius * o.radius);
    return o.height * s * s;
  };
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const Eigen::Vector2d p = X.row(v).head<2>().transpose();
    for (const Vec3& c : b.centres) {
      const double r = (p - c.head<2>()).norm();
      if (r < o.radius) {
        X(v, 2) += profile(r);
        b.truth[v] = 1;
      }
    }
    if (o.ridge_length > 0) {
      const double r = segment_distance(p, r0, r1);
      if (r < o.radius) {
        X(v, 2) += profile(r);
        b.truth[v] = b.ridge[v] = 1;
      }
    }
  }
  set_positions(b.mesh, X);
  return b;
}

BumpyPlate ridge_plate(int n) { return bumpy_plate({.n = n, .bumps = 2, .spacing = 1.0, .ridge_length = 1.2}); }

}  // namespace geotex
