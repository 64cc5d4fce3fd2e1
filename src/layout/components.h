#pragma once
// Algorithm 6: connected components over snaps (knobs in cavities), and the structure-critical
// brick where components meet.
#include <vector>

#include "core/random.h"
#include "layout/layout.h"

namespace lego::layout {

struct ComponentAnalysis {
  int count = 0;               // s_L^I: the number of connected components
  std::vector<int> component;  // by brick id; -1 for dead ids
  std::vector<int> sizes;      // bricks per component
  int critical = -1;           // w_L^I; -1 when there is one component (or none)
};

// Components by depth-first search over snapped bricks, linear in bricks and snaps. With more
// than one component, the critical brick is drawn with probability n_i / sum n_j, n_i being the
// number of other components among its 1-ring neighbours.
// With `ground_connects`, bricks standing on the ground (layer 0) count as joined through it: a
// piece resting on a baseplate or a table is not "floating in the air" (paper section 3), and
// the stability analysis judges it. Without, the paper's strict count over snaps alone.
ComponentAnalysis analyze_components(const Layout& layout, Random& rng,
                                     bool ground_connects = false);

}  // namespace lego::layout
