#pragma once
// A certificate that a model stands, found without solving its LP: forces that balance every
// body within the limits prove C_M ≥ T − (their largest friction force), since the LP's C_M is
// the largest such margin over all balancing forces (PHYSICS.md). Build steps need only this
// (step_stability.h).
#include <functional>
#include <string>
#include <vector>

#include "physics/force_model.h"

namespace lego::physics {

struct Certificate {
  bool found = false;
  double cm = 0;               // C_M is at least this (g·m/s²), when found
  std::vector<double> forces;  // per column of the system, g·m/s², when found
  int local_lps = 0;           // bodies whose forces needed a small LP (the rest: least squares)
  int mended = 0;              // forces a spread left past a bound (brought back when found)
  std::string why_not;         // when not found
};

// Passes each body's load (its weight and what the bodies it holds put on it) to the bodies it
// rests on, from the bodies farthest from the ground (in contacts) down: a few rows at a time,
// so the cost grows with the model's size, not as its LP does. Each body takes the least-squares
// forces without friction when they push only; otherwise the forces whose largest friction is
// least (a small LP); a body that cannot alone shares its load with the bodies near it already
// passed on (one LP over them). The forces found are checked against every row of `system` and
// every bound before they certify anything. Not found: when a body cannot pass its load on within
// the limits (the LP may still find forces: this is a sufficient test, not an exact one). `start`:
// forces to begin from, per column (the step before's, or none): the loads they leave unbalanced
// (the new bricks' weight) are what is passed on.
//
// With `spreading`, its bodies (those of a step the LP solved) are not passed on one by one: the
// sweep passes the other bodies' loads on to them, and its `spread` then moves what they are left
// with as the LP's optimum would (load_spread.h); the forces that leaves past a bound are brought
// back by small LPs near each (not found: too many, or one no LP brings back).
//
// With `wanted_cm`, where the bound falls short of it, small LPs near the largest friction lower
// it, one column at a time, while they can.
struct Spreading {
  std::vector<char> bodies;                                 // per body of the system
  std::function<bool(std::vector<double>& forces)> spread;  // false: it could not
};
Certificate certify(const EquilibriumSystem& system, const ContactGraph& graph,
                    const std::vector<double>& start = {}, const Spreading* spreading = nullptr,
                    double wanted_cm = 0);

}  // namespace lego::physics
