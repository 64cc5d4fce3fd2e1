#pragma once
// Algorithm 2 (layout reconfiguration), Algorithm 5 (single connected component) and
// Algorithm 3 (layout initialization), paper sections 4 and 5.
#include <functional>
#include <span>

#include "core/random.h"
#include "layout/components.h"
#include "layout/merge.h"

namespace lego::layout {

// Equation 1: k = floor(f / N) + 1.
inline int ring_size(int fail_count, int ring_step) {
  return fail_count / ring_step + 1;
}

// Splits the k-ring of the critical bricks into 1x1 bricks with their target colors restored and
// remerges them at random (with their neighbours, so the layout stays maximal). Open an edit
// first to be able to roll it back. Returns the number of bricks split.
size_t reconfigure(Layout& layout, std::span<const int> critical, int k, const MergeRules& rules,
                   Random& rng);

// Fewer 1x1 bricks (paper case study 7: "a few percent"): reconfigures around each 1x1 brick up
// to `tries` times, keeping a candidate only when it has fewer 1x1 bricks and no more bricks.
// Returns how many 1x1 bricks went.
size_t reduce_unit_bricks(Layout& layout, const MergeRules& rules, Random& rng, int tries = 8);

struct ConnectOptions {
  int fail_max = 100;            // consecutive failures before giving up (paper section 8)
  int ring_step = 10;            // N of equation 1
  bool ground_connects = false;  // see analyze_components
  // Called after every iteration (for progress reports); may be empty.
  std::function<void(int iteration, int components, int fail_count)> progress;
};

struct ConnectResult {
  bool single = false;       // one connected component
  int components_start = 0;  // after the random maximal merge
  int components = 0;        // at the end
  int iterations = 0, accepted = 0;
};

// Algorithm 5: reconfigure around the critical brick until one component remains, accepting a
// candidate only when it has fewer components; gives up after fail_max failures in a row.
ConnectResult connect_components(Layout& layout, const MergeRules& rules, Random& rng,
                                 const ConnectOptions& options = {});

// Algorithm 3: a random maximal merge of the 1x1 layout (Algorithm 4), fewer 1x1 bricks, then
// Algorithm 5.
ConnectResult initialize_layout(Layout& layout, const MergeRules& rules, Random& rng,
                                const ConnectOptions& options = {});

}  // namespace lego::layout
