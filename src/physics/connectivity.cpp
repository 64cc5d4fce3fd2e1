#include "physics/connectivity.h"

#include <numeric>

namespace lego::physics {
namespace {

struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

}  // namespace

Connectivity analyze_connectivity(int brick_count, const ContactGraph& graph) {
  DisjointSets sets(brick_count);
  for (const auto& c : graph.stacked)
    if (c.snap() && c.lower != kGround) sets.join(c.lower, c.upper);
  Connectivity out;
  out.component.assign(brick_count, -1);
  std::vector<int> id_of_root(brick_count, -1);
  for (int i = 0; i < brick_count; ++i) {
    int root = sets.find(i);
    if (id_of_root[root] < 0) id_of_root[root] = out.component_count++;
    out.component[i] = id_of_root[root];
  }
  out.grounded.assign(out.component_count, 0);
  for (const auto& c : graph.stacked)
    if (c.lower == kGround) out.grounded[out.component[c.upper]] = 1;
  for (int i = 0; i < brick_count; ++i)
    if (!out.grounded[out.component[i]]) out.floating.push_back(i);
  return out;
}

}  // namespace lego::physics
