#pragma once
// The order in which a person builds an assembly, step by step, so that every step stands
// (the paper's first limitation, section 8: a stable layout can fall while being built).
#include <functional>
#include <string>
#include <vector>

#include "core/assembly.h"
#include "physics/stability.h"

namespace lego::layout {

struct BuildOrderOptions {
  physics::StabilityOptions stability;
  double min_cm_gf = 0;  // a step stands when its C_M / g is above this
  // Tries per step to make a failing step stand by holding its weakest new bricks back.
  int repairs_per_step = 4;
  // New bricks in one step at most (nearby_groups.h): a layer with more is built in groups of
  // nearby bricks, a step each. 0: a layer per step.
  int max_new_bricks = 30;
  // False: the order by studs alone, no step analysed (one analysis per step costs about half
  // the final model's each; the report then says the steps were not analysed).
  bool analyse = true;
  // A step stands when a certificate shows it (physics/step_stability.h); the LP only where no
  // certificate is found, and for the weakest step's exact C_M. False: the LP for every step.
  bool certify = true;
  // Without certificates, two steps analysed at a time (the next planned as if this one
  // stands); with them, one by one (plan_build_order says why), the next step's model and
  // system made while this one is decided. False: one thing at a time. The order is the same.
  bool side_by_side = true;
  // With certificates: after a step the LP solved on `from_bricks` bricks or more, the model
  // `steps` steps on (planned as if they stand) is solved by the LP while they are certified, in
  // another thread with side_by_side (plan_build_order says why). steps 0: never.
  struct SolveAhead {
    int steps = 25;
    int from_bricks = 1000;
  } solve_ahead;
  std::function<void(int step, int steps_so_far, double seconds)> progress;  // may be empty
  // How a step that falls names a brick of the assembly (legolize: its part and where it is on
  // the model, layout/where_on_model.h); empty: its part and lattice corner.
  std::function<std::string(int brick)> describe;
};

// The model after one step, as brickcheck --steps analyses it (no external loads: they are
// the finished model's).
struct BuildStep {
  int layer = 0;       // the lowest layer (bottom, plates) of the step's new bricks
  int new_bricks = 0;  // placed in this step
  int bricks = 0;      // placed so far
  physics::StabilityStatus status = physics::StabilityStatus::Empty;
  double cm_gf = 0;        // valid when status is Solved
  bool certified = false;  // cm_gf is a certified lower bound (physics/certificate.h), not exact
  int floating = 0;        // bricks placed so far that reach no ground
  bool analysed = false;
  bool stands = false;  // when analysed
  std::string why;      // when it does not stand: what holds it back
  // When it does not stand: its bricks (of the assembly) that float, else those no forces
  // balance, else the two its weakest contact joins.
  std::vector<int> falling;
};

struct BuildOrder {
  std::vector<int> step_of;  // per brick of the assembly, 1-based
  std::vector<BuildStep> steps;
  int held_back = 0;  // bricks moved to a later step than their layer's to make a step stand
  // The first steps build the columns standing on the ground: how many (0: none).
  int supports_steps = 0;
  int analyses = 0;      // stability analyses run
  int solved_ahead = 0;  // steps the LP solved while the steps before them were certified
  double seconds = 0;
  // Of the analyses, those the LP solved (steps no certificate decided, the weakest step's exact
  // C_M) and their LPs' time: on another thread for the steps solved ahead.
  int lp_solves = 0;
  double lp_seconds = 0;
  bool all_stand() const;  // every step analysed and standing
  int certified_steps() const;
  // The smallest C_M / g of the analysed steps is a certificate's bound, not the LP's value.
  bool weakest_is_a_bound() const;
  // The smallest C_M / g of the analysed steps (-inf when one has no number, +inf when none is
  // analysed).
  double min_cm_gf() const;
};

// Orders the bricks layer by layer from the ground up, supports (Brick::support) standing on the
// ground first in steps of their own. Step k takes every brick of layers up to
// the k-th that a brick already placed (or the ground) holds by its studs: a brick hanging from
// the layer above comes with the next layer, in the step after the brick that holds it. Of more
// than max_new_bricks, a group of nearby ones; the layer's others follow in the next steps (bricks
// of other layers that come along go first, in a step of their own, where with the group they
// would be more). A group that no certificate shows standing is decided by the LP. Each
// step is analysed; when one does not stand, its new bricks that make it fall (those no forces
// balance, else the ends of its weakest contacts) wait for the next layer, and the step is tried
// again.
BuildOrder plan_build_order(const Assembly& assembly, const BuildOrderOptions& options);

// The assembly's bricks with Brick::source.step from the order, sorted by step (stably), and the
// steps' falling bricks renumbered with them; the permutation (new index -> old index) lets
// callers move what else refers to bricks by index.
std::vector<int> apply_build_order(Assembly& assembly, BuildOrder& order);

}  // namespace lego::layout
