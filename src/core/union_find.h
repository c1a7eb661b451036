// Disjoint sets over 0 … n − 1 whose root is the smallest index of its set (mesh_repair.cpp's corners of one
// vertex, weld.cpp's coincident vertices and fans).
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace geotex::detail {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace geotex::detail
