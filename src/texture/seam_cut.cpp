// Graph-cut seams (seam_cut.h).

#include "seam_cut.h"

#include <algorithm>
#include <limits>

namespace geotex::detail {

namespace {
constexpr double kEps = 1e-15;
}

MaxFlow::MaxFlow(int nodes) : head_(nodes, -1), level_(nodes), it_(nodes) {}

void MaxFlow::add(int a, int b, double ab, double ba) {
  link(a, b, ab);
  link(b, a, ba);
}

double MaxFlow::run(int s, int t) {
  double total = 0;
  while (levels(s, t)) {
    it_ = head_;
    while (const double f = push(s, t, std::numeric_limits<double>::infinity())) total += f;
  }
  return total;
}

std::vector<char> MaxFlow::source_side(int s) const {
  std::vector<char> seen(head_.size(), 0);
  std::vector<int> stack{s};
  seen[s] = 1;
  while (!stack.empty()) {
    const int a = stack.back();
    stack.pop_back();
    for (int e = head_[a]; e >= 0; e = next_[e])
      if (cap_[e] > kEps && !seen[to_[e]]) seen[to_[e]] = 1, stack.push_back(to_[e]);
  }
  return seen;
}

void MaxFlow::link(int a, int b, double c) {
  to_.push_back(b);
  cap_.push_back(c);
  next_.push_back(head_[a]);
  head_[a] = static_cast<int>(to_.size()) - 1;
}

bool MaxFlow::levels(int s, int t) {
  std::fill(level_.begin(), level_.end(), -1);
  std::vector<int> queue{s};
  level_[s] = 0;
  for (size_t i = 0; i < queue.size(); ++i)
    for (int e = head_[queue[i]]; e >= 0; e = next_[e])
      if (cap_[e] > kEps && level_[to_[e]] < 0) level_[to_[e]] = level_[queue[i]] + 1, queue.push_back(to_[e]);
  return level_[t] >= 0;
}

double MaxFlow::push(int a, int t, double f) {
  if (a == t) return f;
  for (int& e = it_[a]; e >= 0; e = next_[e]) {
    const int b = to_[e];
    if (cap_[e] <= kEps || level_[b] != level_[a] + 1) continue;
    if (const double g = push(b, t, std::min(f, cap_[e])); g > 0) {
      cap_[e] -= g;
      cap_[e ^ 1] += g;
      return g;
    }
  }
  return 0;
}

namespace {

// Rings from the cut within the overlap (node ≥ 0), up to \p feather: the shares mixed there.
void feather_cut(const Mesh& mesh, const std::vector<int>& vertices, const std::vector<int>& slot,
                 const std::vector<int>& node, int feather, std::vector<double>& share) {
  const size_t k = vertices.size();
  std::vector<int> ring(k, -1), queue;
  for (size_t s = 0; s < k; ++s) {
    if (node[s] < 0) continue;
    for (auto wh : mesh.vv_range(mesh.vertex_handle(vertices[s]))) {
      const int j = slot[wh.idx()];
      if (j >= 0 && node[j] >= 0 && share[j] != share[s]) {
        ring[s] = 0, queue.push_back(static_cast<int>(s));
        break;
      }
    }
  }
  for (size_t i = 0; i < queue.size(); ++i) {
    const int s = queue[i];
    if (ring[s] + 1 >= feather) continue;
    for (auto wh : mesh.vv_range(mesh.vertex_handle(vertices[s]))) {
      const int j = slot[wh.idx()];
      if (j >= 0 && node[j] >= 0 && ring[j] < 0 && share[j] == share[s]) ring[j] = ring[s] + 1, queue.push_back(j);
    }
  }
  for (size_t s = 0; s < k; ++s) {
    if (ring[s] < 0) continue;
    const double own = 0.5 + 0.5 * (ring[s] + 0.5) / (feather + 0.5);  // ½ at the cut, → 1 at `feather` rings
    share[s] = share[s] > 0 ? own : 1 - own;
  }
}

}  // namespace

std::vector<double> seam_cut(const Mesh& mesh, const std::vector<int>& vertices, const std::vector<Vec3>& fresh,
                             const std::vector<Vec3>& old, const std::function<bool(int)>& written, int feather,
                             const std::vector<double>& cost_fresh, const std::vector<double>& cost_old,
                             bool take_centre) {
  const size_t k = vertices.size();
  std::vector<int> slot(mesh.n_vertices(), -1), node(k, -1);  // overlap vertices: their node (0: keep, 1: new)
  for (size_t s = 0; s < k; ++s) slot[vertices[s]] = static_cast<int>(s);
  int nodes = 2;
  for (size_t s = 0; s < k; ++s)
    if (written(vertices[s])) node[s] = nodes++;
  std::vector<double> share(k, 1.0);
  if (nodes == 2) return share;
  struct Link {
    int a, b;
    double c;
  };
  std::vector<Link> links;
  std::vector<char> keep(nodes, 0), renew(nodes, 0);
  double total = 0;
  bool any_new = false;
  for (size_t s = 0; s < k; ++s) {
    if (node[s] < 0) continue;
    const int v = vertices[s];
    const double ds = (fresh[s] - old[s]).norm();
    for (auto wh : mesh.vv_range(mesh.vertex_handle(v))) {
      const int w = wh.idx(), j = slot[w];
      if (j < 0) {
        if (written(w)) keep[node[s]] = 1;
        continue;
      }
      if (node[j] < 0) {
        renew[node[s]] = 1, any_new = true;
        continue;
      }
      if (w < v) continue;  // each edge once
      const double c = ds + (fresh[j] - old[j]).norm();
      links.push_back({node[s], node[j], c});
      total += c;
    }
  }
  if (take_centre && !any_new && node[0] >= 0) renew[node[0]] = 1;
  std::vector<double> take(nodes, 0.0), stay(nodes, 0.0);  // data costs of taking / keeping
  for (size_t s = 0; s < k; ++s) {
    if (node[s] < 0) continue;
    if (!cost_fresh.empty()) take[node[s]] = cost_fresh[s], total += cost_fresh[s];
    if (!cost_old.empty()) stay[node[s]] = cost_old[s], total += cost_old[s];
  }
  const double inf = 2 * total + 1;
  MaxFlow g(nodes);
  for (const Link& l : links) g.add(l.a, l.b, l.c, l.c);
  for (int i = 2; i < nodes; ++i) {  // source → i is cut when i takes the patch's, i → sink when it keeps
    if (keep[i] || take[i] > 0) g.add(0, i, keep[i] ? inf : take[i], 0);
    if (renew[i] || stay[i] > 0) g.add(i, 1, renew[i] ? inf : stay[i], 0);
  }
  g.run(0, 1);
  const std::vector<char> side = g.source_side(0);
  for (size_t s = 0; s < k; ++s)
    if (node[s] >= 0 && side[node[s]]) share[s] = 0;
  if (feather > 0) feather_cut(mesh, vertices, slot, node, feather, share);
  return share;
}

}  // namespace geotex::detail
