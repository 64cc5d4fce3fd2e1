#pragma once
// Algorithm 7: stability-aware refinement with Algorithm 8 (the force-based C_M of PHYSICS.md)
// as its metric, reconfiguring around the bottleneck contact.
#include <functional>
#include <string>

#include "core/brick_catalog.h"
#include "core/random.h"
#include "layout/merge.h"
#include "layout/to_assembly.h"
#include "physics/stability.h"

namespace lego::layout {

struct RefineProgress {
  int iteration = 0, accepted = 0, fail_count = 0, lp_solves = 0;
  double cm_gf = 0;  // of the current layout (-inf when no equilibrium)
  double seconds = 0;
};

struct RefineOptions {
  double min_cm_gf = 0;  // stop once C_M / g exceeds this (paper footnote 7)
  int fail_max = 100;
  int ring_step = 10;            // N of equation 1
  bool ground_connects = false;  // for the single-component check, see analyze_components
  double max_seconds = 1e30;     // stop refining after this long (the result says so)
  // Candidates generated one after another (each counting as an iteration, with k from the fail
  // count so far), then analysed; the best that beats the current C_M is kept. 1 is the paper's
  // sequential loop. The result depends on this number, never on `side_by_side` or timing.
  int candidates_per_round = 2;
  // The round's candidates analysed at the same time, one thread each (else one after another).
  bool side_by_side = true;
  // Before a candidate gets the whole model's analysis, an upper bound on its C_M from the
  // reconfigured bricks, those sharing a force with them and this many more rings of contacts
  // (physics/local_bounds.h): a candidate that cannot beat the current C_M is rejected on it,
  // which leaves the refinement's course as it was. Negative: never. Measured on the table
  // sample at twice its size, ring 0 rejected 99 of 119 candidates in 74 s of bounds, ring 1
  // 97 in 91 s, ring 2 98 in 137 s.
  int bound_ring = 0;
  physics::StabilityOptions stability;
  Loads loads;
  int inside_color = 72;
  int support_color = kDefaultSupportColor;
  std::function<void(const RefineProgress&)> progress;  // after every iteration; may be empty
};

struct RefineResult {
  physics::StabilityResult initial, final;  // of the layout before and after
  bool stable = false;                      // final C_M / g > min_cm_gf
  bool gave_up = false;                     // fail_MAX failures in a row
  bool out_of_time = false;                 // max_seconds ran out
  int iterations = 0, accepted = 0, lp_solves = 0;
  int rejected_disconnected = 0;  // candidates discarded for not being one component
  int rejected_by_bound = 0;      // candidates whose local upper bound could not beat C_M
  double bound_seconds = 0;       // spent computing local bounds
};

// C_M / g as the refinement compares it: -inf when the analysis gives no number.
double comparable_cm_gf(const physics::StabilityResult& result);

// Runs Algorithm 7 on a single-connected layout, changing it in place.
RefineResult refine_layout(Layout& layout, const BrickCatalog& catalog, const MergeRules& rules,
                           Random& rng, const RefineOptions& options);

}  // namespace lego::layout
