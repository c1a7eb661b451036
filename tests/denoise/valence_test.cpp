// Denoising at vertices of very high valence: the per-vertex steps must stay linear in the valence and
// give what the straightforward formulas give (colourings, edge support, local vertex energies).

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/surfel.h"
#include "geotex/core/random.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "../../src/denoise/mrf_internal.h"

using namespace geotex;
using namespace geotex::detail;

namespace {

// A closed double cone: a rim of n vertices on the unit circle, two apexes of valence n.
Mesh spindle(int n, double height = 0.5) {
  MatrixX3d V(n + 2, 3);
  MatrixX3i F(2 * n, 3);
  for (int i = 0; i < n; ++i) V.row(i) << std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0.0;
  V.row(n) << 0, 0, height;
  V.row(n + 1) << 0, 0, -height;
  for (int i = 0; i < n; ++i) {
    F.row(i) << i, (i + 1) % n, n;
    F.row(n + i) << (i + 1) % n, i, n + 1;
  }
  return make_mesh(V, F);
}

// The textbook greedy edge colouring: each edge takes the smallest colour no coloured edge at its ends has.
std::vector<int> reference_edge_colours(const Topology& T) {
  std::vector<int> colour(T.nE, -1);
  for (int e = 0; e < T.nE; ++e) {
    std::set<int> used;
    for (int s = 0; s < 2; ++s) {
      const int v = T.E[2 * e + s];
      for (int k = T.ve_off[v]; k < T.ve_off[v + 1]; ++k) used.insert(colour[T.ve[k]]);
    }
    int c = 0;
    while (used.count(c)) ++c;
    colour[e] = c;
  }
  return colour;
}

Mesh noisy(const Mesh& m, double sigma) {
  NoiseOptions o;
  o.sigma = sigma;
  Mesh out = m;
  set_positions(out, add_noise(m, o));
  return out;
}

}  // namespace

TEST(HighValence, EdgeColouringIsValidFewColoursAndTheGreedyOne) {
  const Mesh m = spindle(3000);
  const Topology T(m);
  const auto& classes = T.edge_colours();
  std::vector<int> colour(T.nE, -1);
  for (size_t c = 0; c < classes.size(); ++c) {
    std::set<int> ends;
    for (int e : classes[c]) {
      EXPECT_EQ(colour[e], -1) << "edge " << e << " in two classes";
      colour[e] = static_cast<int>(c);
      EXPECT_TRUE(ends.insert(T.E[2 * e]).second && ends.insert(T.E[2 * e + 1]).second)
          << "two edges of colour " << c << " share a vertex";
    }
  }
  for (int e = 0; e < T.nE; ++e) EXPECT_GE(colour[e], 0);
  // The apexes' 3000 edges need 3000 colours; greedy may use a few more, never twice as many.
  EXPECT_GE(classes.size(), 3000u);
  EXPECT_LE(classes.size(), 3004u);
  // Exactly the textbook greedy colouring (smaller spindle: the reference is quadratic).
  const Topology t(spindle(200));
  const std::vector<int> ref = reference_edge_colours(t);
  for (size_t c = 0; c < t.edge_colours().size(); ++c)
    for (int e : t.edge_colours()[c]) EXPECT_EQ(ref[e], static_cast<int>(c));
}

TEST(HighValence, EdgeSupportAtAnApexMatchesTheDirectSum) {
  const Mesh m = noisy(spindle(500), 0.05);
  const Topology T(m);
  const std::vector<double> x = flat(positions(m), 1.0);
  std::vector<double> n(3 * T.nF);
  compute_normals(T, x.data(), n.data(), nullptr);
  EdgeField field(T, EdgeProcessOptions{});
  field.update(x.data(), n.data());
  Rng rng(3);
  std::vector<double> eps(T.nE);
  for (double& e : eps) e = rng.uniform() < 0.3 ? rng.uniform() : 0.0;
  auto direct = [&](int e) {  // ∂U_E/∂ε_e by Eq. (6.9–6.11), term by term
    double support = 0;
    for (int s = 0; s < 2; ++s) {
      const int v = T.E[2 * e + s];
      for (int k = T.ve_off[v]; k < T.ve_off[v + 1]; ++k)
        if (T.ve[k] != e) support += field.cos_theta(e, T.ve[k], v) * eps[T.ve[k]];
    }
    return (field.opt.phi0_deg * M_PI / 180 - field.phi[e]) - field.opt.support_weight * support;
  };
  field.gather(eps.data());
  for (int e = 0; e < T.nE; ++e) ASSERT_NEAR(field.field(e, eps.data()), direct(e), 1e-10) << e;
  // The sums follow a Metropolis sweep's changes (hot, so that many labels change).
  // After a hot Metropolis sweep (many labels change, each updating the sums), the sums are those of
  // the new labels (metropolis() ends with energy(), which gathers afresh: check the increments here).
  std::vector<double> before = eps;
  field.gather(eps.data());
  for (const auto& cls : T.edge_colours())
    for (int e : cls) {
      const double proposal = rng.uniform();
      field.changed(e, proposal - eps[e]);
      eps[e] = proposal;
    }
  for (int e = 0; e < T.nE; ++e) ASSERT_NEAR(field.field(e, eps.data()), direct(e), 1e-10) << e;
  EXPECT_NE(before, eps);
}

TEST(HighValence, LocalVertexEnergyAtAnApexIsTheChangeOfTheTotal) {
  // Every face around the apex counts (a valence cap once dropped those beyond the 64th).
  const Mesh m = noisy(spindle(400), 0.05);
  const Topology T(m);
  const std::vector<double> x0 = flat(positions(m), 1.0);
  std::vector<double> w(T.nE, 1.0), x = x0, n(3 * T.nF);
  Rng rng(4);
  for (double& v : w) v = rng.uniform();
  const VertexProblem P(T, x0.data(), w.data(), 0.1, SmoothnessPotential::Quadratic);
  compute_normals(T, x.data(), n.data(), nullptr);
  const int apex = 400;
  const Vec3 old = vec(&x[3 * apex]), p = old + Vec3(0.01, -0.02, 0.03);
  const double U0 = P.value(x.data());
  const double local_change = P.local(apex, p, x.data(), n.data(), nullptr) - P.local(apex, old, x.data(), n.data(), nullptr);
  put(&x[3 * apex], p);
  const double total_change = P.value(x.data()) - U0;
  EXPECT_NEAR(local_change, total_change, 1e-9 * std::max(1.0, std::abs(total_change)));
  EXPECT_GT(std::abs(total_change), 1e-6);
}

TEST(HighValence, EveryDenoiserRunsOnASpindleAndKeepsItsConnectivity) {
  const Mesh m = noisy(spindle(3000), 0.02);
  MrfOptions mo;
  mo.iterations = 5;
  mo.final_sweeps = 5;
  MrfNormalOptions no;
  no.iterations = 5;
  const MrfResult a = mrf_denoise(m, mo), b = mrf_normal_denoise(m, no);
  EXPECT_TRUE(a.positions.allFinite());
  EXPECT_TRUE(b.positions.allFinite());
  for (const SurfelRetrieval r : {SurfelRetrieval::Fit, SurfelRetrieval::Dual}) {
    SurfelDenoiseOptions so;
    so.retrieval = r;
    so.iterations = 5;
    so.candidates = true;
    const SurfelDenoiseResult s = surfel_denoise(m, so);
    EXPECT_TRUE(positions(s.mesh).allFinite());
    if (r == SurfelRetrieval::Fit) EXPECT_EQ(s.mesh.n_faces(), m.n_faces());
    else EXPECT_EQ(s.mesh.n_vertices(), m.n_faces());
  }
}
