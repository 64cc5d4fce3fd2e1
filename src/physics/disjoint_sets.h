#pragma once
// Union-find over 0..n-1, for grouping what touches what (snapped components, carried groups).
#include <algorithm>
#include <numeric>
#include <vector>

namespace lego::physics {

struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(size_t(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
    return i;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);  // the lowest index leads
  }
};

}  // namespace lego::physics
