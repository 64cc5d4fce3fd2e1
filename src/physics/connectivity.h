#pragma once
#include <vector>

#include "physics/contact_graph.h"

namespace lego::physics {

// Bricks grouped by snaps (stud connections) and assumed-rigid joints; face contacts hold nothing
// together. A component reaches the ground through a snap to the ground or to a fixed brick, or
// by resting on the ground, a fixed brick or a grounded component (a face contact from below, but
// not one that is misaligned: a part placed off the lattice on studs does not rest on them).
// Fixed bricks are the ground: they belong to no component.
struct Connectivity {
  std::vector<int> component;  // per brick, 0-based in order of first brick; -1 for fixed bricks
  int component_count = 0;
  std::vector<char> grounded;         // per component
  std::vector<int> floating;          // bricks of components that do not reach the ground
  std::vector<int> floating_carried;  // carried parts (Assembly::carried) that rest on nothing
                                      // that stands

  bool all_grounded() const { return floating.empty() && floating_carried.empty(); }
};

Connectivity analyze_connectivity(int brick_count, const ContactGraph& graph);

}  // namespace lego::physics
