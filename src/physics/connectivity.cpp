#include "physics/connectivity.h"

#include <algorithm>

#include "physics/disjoint_sets.h"

namespace lego::physics {

Connectivity analyze_connectivity(int brick_count, const ContactGraph& graph) {
  auto fixed = [&](int b) {
    return b == kGround || (!graph.fixed.empty() && graph.fixed[size_t(b)]);
  };
  DisjointSets sets(brick_count);
  for (const auto& c : graph.contacts)
    if ((c.snap() || c.joint) && !fixed(c.lower) && !fixed(c.upper)) sets.join(c.lower, c.upper);
  Connectivity out;
  out.component.assign(size_t(brick_count), -1);
  std::vector<int> id_of_root(size_t(brick_count), -1);
  for (int i = 0; i < brick_count; ++i) {
    if (fixed(i)) continue;
    int root = sets.find(i);
    if (id_of_root[size_t(root)] < 0) id_of_root[size_t(root)] = out.component_count++;
    out.component[size_t(i)] = id_of_root[size_t(root)];
  }
  // Grounded: held by the ground, then whatever rests on something grounded, until nothing moves.
  out.grounded.assign(size_t(out.component_count), 0);
  std::vector<std::vector<int>> rests_on(size_t(out.component_count));  // component -> above it
  std::vector<int> queue;
  auto ground = [&](int component) {
    if (!out.grounded[size_t(component)]) {
      out.grounded[size_t(component)] = 1;
      queue.push_back(component);
    }
  };
  for (const auto& c : graph.contacts) {
    // A part resting off the lattice (on studs it does not take) is not held by that rest.
    const bool from_below = c.direction == kPlusY && !c.snap() && !c.misaligned;
    if (fixed(c.lower) && !fixed(c.upper) && (c.snap() || c.joint || from_below))
      ground(out.component[size_t(c.upper)]);
    else if (fixed(c.upper) && !fixed(c.lower) && (c.snap() || c.joint))
      ground(out.component[size_t(c.lower)]);
    else if (from_below && !fixed(c.lower) && !fixed(c.upper))
      rests_on[size_t(out.component[size_t(c.lower)])].push_back(out.component[size_t(c.upper)]);
  }
  while (!queue.empty()) {
    const int component = queue.back();
    queue.pop_back();
    for (int above : rests_on[size_t(component)]) ground(above);
  }
  for (int i = 0; i < brick_count; ++i)
    if (!fixed(i) && !out.grounded[size_t(out.component[size_t(i)])]) out.floating.push_back(i);
  for (const auto& group : graph.carried_groups) {
    bool held = group.on_ground || !group.rests_on_fixed.empty();
    for (int b : group.joins) held = held || out.grounded[size_t(out.component[size_t(b)])];
    if (!held)
      out.floating_carried.insert(out.floating_carried.end(), group.carried.begin(),
                                  group.carried.end());
  }
  std::sort(out.floating_carried.begin(), out.floating_carried.end());
  return out;
}

}  // namespace lego::physics
