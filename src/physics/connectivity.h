#pragma once
#include <vector>

#include "physics/contact_graph.h"

namespace lego::physics {

// Bricks grouped by snaps (stacked contacts with engaged knobs). Side contacts hold nothing
// together. A component is grounded when one of its bricks stands on the ground.
struct Connectivity {
  std::vector<int> component;  // per brick, 0-based, numbered in order of first brick
  int component_count = 0;
  std::vector<char> grounded;  // per component
  std::vector<int> floating;   // bricks of components that do not touch the ground

  bool all_grounded() const { return floating.empty(); }
};

Connectivity analyze_connectivity(int brick_count, const ContactGraph& graph);

}  // namespace lego::physics
