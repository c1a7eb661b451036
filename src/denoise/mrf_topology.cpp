// Mesh connectivity as flat arrays for the MRF denoisers (mrf_internal.h): faces, edges, the faces
// and edges around each vertex, colour classes of sites that may be updated together, face normals.

#include <algorithm>

#include "geotex/core/geometry.h"
#include "mrf_internal.h"

namespace geotex::detail {

Topology::Topology(const Mesh& mesh) {
  nV = static_cast<int>(mesh.n_vertices());
  nF = static_cast<int>(mesh.n_faces());
  nE = static_cast<int>(mesh.n_edges());
  F.resize(3 * nF);
  fe.resize(3 * nF);
  for (int f = 0; f < nF; ++f) {
    auto h = mesh.halfedge_handle(mesh.face_handle(f));
    for (int m = 0; m < 3; ++m) {
      F[3 * f + m] = mesh.from_vertex_handle(h).idx();
      fe[3 * f + m] = mesh.edge_handle(h).idx();  // edge from corner m to corner m+1
      h = mesh.next_halfedge_handle(h);
    }
  }
  E.resize(2 * nE);
  ef.resize(2 * nE);
  for (int e = 0; e < nE; ++e) {
    const auto eh = mesh.edge_handle(e);
    for (int s = 0; s < 2; ++s) {
      const auto h = mesh.halfedge_handle(eh, s);
      ef[2 * e + s] = mesh.face_handle(h).is_valid() ? mesh.face_handle(h).idx() : -1;
    }
    const auto h0 = mesh.halfedge_handle(eh, 0);
    E[2 * e] = mesh.from_vertex_handle(h0).idx();
    E[2 * e + 1] = mesh.to_vertex_handle(h0).idx();
  }
  // Vertex → incident faces (with the corner), vertex → incident edges (CSR).
  vf_off.assign(nV + 1, 0);
  for (int c = 0; c < 3 * nF; ++c) ++vf_off[F[c] + 1];
  for (int v = 0; v < nV; ++v) vf_off[v + 1] += vf_off[v];
  vf.resize(3 * nF);
  {
    std::vector<int> fill(vf_off.begin(), vf_off.end() - 1);
    for (int c = 0; c < 3 * nF; ++c) vf[fill[F[c]]++] = c;  // corner id: 3 f + m
  }
  vf_pos.resize(3 * nF);
  for (int v = 0; v < nV; ++v)
    for (int k = vf_off[v]; k < vf_off[v + 1]; ++k) vf_pos[vf[k]] = k - vf_off[v];
  ve_off.assign(nV + 1, 0);
  for (int e = 0; e < nE; ++e) {
    ++ve_off[E[2 * e] + 1];
    ++ve_off[E[2 * e + 1] + 1];
  }
  for (int v = 0; v < nV; ++v) ve_off[v + 1] += ve_off[v];
  ve.resize(2 * nE);
  {
    std::vector<int> fill(ve_off.begin(), ve_off.end() - 1);
    for (int e = 0; e < nE; ++e) {
      ve[fill[E[2 * e]]++] = e;
      ve[fill[E[2 * e + 1]]++] = e;
    }
  }
}

namespace {
// Greedy colouring given each site's neighbour list (a callback filling `nb`).
template <class Neighbours>
std::vector<std::vector<int>> greedy_colouring(int n, Neighbours&& neighbours) {
  std::vector<int> colour(n, -1), stamp;
  std::vector<int> nb;
  int n_colours = 0;
  for (int s = 0; s < n; ++s) {
    nb.clear();
    neighbours(s, nb);
    if (static_cast<int>(stamp.size()) < n_colours + 1) stamp.resize(n_colours + 1, -1);
    for (int t : nb)
      if (t != s && colour[t] >= 0) stamp[colour[t]] = s;
    int c = 0;
    while (c < n_colours && stamp[c] == s) ++c;
    colour[s] = c;
    n_colours = std::max(n_colours, c + 1);
  }
  std::vector<std::vector<int>> classes(n_colours);
  for (int s = 0; s < n; ++s) classes[colour[s]].push_back(s);
  return classes;
}
}  // namespace

const std::vector<std::vector<int>>& Topology::vertex_colours() const {
  if (vertex_colours_.empty() && nV > 0) {
    // Conflict: b is a corner of a face that shares an edge with (or is) a face around a.
    vertex_colours_ = greedy_colouring(nV, [&](int a, std::vector<int>& nb) {
      for (int k = vf_off[a]; k < vf_off[a + 1]; ++k) {
        const int f = vf[k] / 3;
        for (int m = 0; m < 3; ++m) {
          const int e = fe[3 * f + m];
          for (int s = 0; s < 2; ++s) {
            const int g = ef[2 * e + s];
            if (g < 0) continue;
            for (int q = 0; q < 3; ++q) nb.push_back(F[3 * g + q]);
          }
        }
      }
    });
  }
  return vertex_colours_;
}

const std::vector<std::vector<int>>& Topology::edge_colours() const {
  if (edge_colours_.empty() && nE > 0) {
    // Greedy, as greedy_colouring(): each edge in turn takes the smallest colour that no coloured edge at
    // either end has. At a vertex of high valence the colours taken there are kept in a table, with the
    // lowest free one, instead of being collected from all its edges for each of them: the colouring
    // costs O(#E) whatever the valences (a vertex of valence d would cost O(d²)).
    std::vector<int> colour(nE, -1), stamp, slot(nV, -1), lowest_free;
    std::vector<std::vector<char>> taken;
    for (int v = 0; v < nV; ++v)
      if (ve_off[v + 1] - ve_off[v] > kHeavyValence) {
        slot[v] = static_cast<int>(taken.size());
        taken.emplace_back();
        lowest_free.push_back(0);
      }
    int n_colours = 0;
    for (int e = 0; e < nE; ++e) {
      if (static_cast<int>(stamp.size()) < n_colours + 1) stamp.resize(n_colours + 1, -1);
      int c = 0;
      for (int s = 0; s < 2; ++s) {
        const int v = E[2 * e + s];
        if (slot[v] >= 0) {
          c = std::max(c, lowest_free[slot[v]]);
          continue;
        }
        for (int k = ve_off[v]; k < ve_off[v + 1]; ++k)
          if (colour[ve[k]] >= 0) stamp[colour[ve[k]]] = e;
      }
      auto is_free = [&](int c) {
        if (c < n_colours && stamp[c] == e) return false;
        for (int s = 0; s < 2; ++s) {
          const int h = slot[E[2 * e + s]];
          if (h >= 0 && c < static_cast<int>(taken[h].size()) && taken[h][c]) return false;
        }
        return true;
      };
      while (!is_free(c)) ++c;
      colour[e] = c;
      n_colours = std::max(n_colours, c + 1);
      for (int s = 0; s < 2; ++s) {
        const int h = slot[E[2 * e + s]];
        if (h < 0) continue;
        if (static_cast<int>(taken[h].size()) <= c) taken[h].resize(c + 1, 0);
        taken[h][c] = 1;
        while (lowest_free[h] < static_cast<int>(taken[h].size()) && taken[h][lowest_free[h]]) ++lowest_free[h];
      }
    }
    edge_colours_.assign(n_colours, {});
    for (int e = 0; e < nE; ++e) edge_colours_[colour[e]].push_back(e);
  }
  return edge_colours_;
}

const std::vector<std::vector<int>>& Topology::face_colours() const {
  if (face_colours_.empty() && nF > 0) {
    face_colours_ = greedy_colouring(nF, [&](int f, std::vector<int>& nb) {
      for (int m = 0; m < 3; ++m) {
        const int e = fe[3 * f + m];
        for (int s = 0; s < 2; ++s)
          if (ef[2 * e + s] >= 0) nb.push_back(ef[2 * e + s]);
      }
    });
  }
  return face_colours_;
}

uint64_t site_seed(uint64_t seed, uint64_t sweep, uint64_t site) {
  return seed * 0x9E3779B97F4A7C15ull + (sweep + 1) * 0xD1B54A32D192ED03ull + (site + 1) * 0xABC98388FB8FAC03ull;
}

void compute_normals(const Topology& T, const double* x, double* n, double* inv_len) {
#pragma omp parallel for schedule(static) if (T.nF >= min_parallel)
  for (int f = 0; f < T.nF; ++f) {
    const double* a = x + 3 * T.F[3 * f];
    const double* b = x + 3 * T.F[3 * f + 1];
    const double* c = x + 3 * T.F[3 * f + 2];
    const Vec3 N = (Vec3(b[0], b[1], b[2]) - Vec3(a[0], a[1], a[2])).cross(Vec3(c[0], c[1], c[2]) - Vec3(a[0], a[1], a[2]));
    const double len = N.norm();
    const double inv = len > 1e-300 ? 1.0 / len : 0.0;
    for (int d = 0; d < 3; ++d) n[3 * f + d] = N[d] * inv;
    if (inv_len) inv_len[f] = inv;
  }
}

std::vector<double> flat(const MatrixX3d& X, double scale) {
  std::vector<double> x(3 * X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (int d = 0; d < 3; ++d) x[3 * i + d] = X(i, d) / scale;
  return x;
}

MatrixX3d unflat(const double* x, int n, double scale) {
  MatrixX3d X(n, 3);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) X(i, d) = x[3 * i + d] * scale;
  return X;
}

}  // namespace geotex::detail
