#include "layout/build_order.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "core/stopwatch.h"
#include "core/text.h"
#include "layout/nearby_groups.h"
#include "physics/contact_graph.h"
#include "physics/step_stability.h"

namespace lego::layout {

namespace {

// Steps that fall one after another are beyond holding bricks back (a spider's legs leaning out
// until the body ties them): past this many, the rest are analysed but not repaired.
constexpr int kStopRepairingAfter = 3;

// The model as it stands after a step: the bricks placed so far, in the assembly's order.
Assembly partial_assembly(const Assembly& whole, const std::vector<char>& in,
                          std::vector<int>& whole_index) {
  Assembly partial;
  partial.origin_ldu = whole.origin_ldu;
  partial.ground_height = whole.ground_height;
  whole_index.clear();
  for (int i = 0; i < int(whole.bricks.size()); ++i)
    if (in[size_t(i)]) {
      whole_index.push_back(i);
      partial.bricks.push_back(whole.bricks[size_t(i)]);
    }
  return partial;
}

std::string describe(const Assembly& a, int brick) {
  if (brick == physics::kGround) return "the ground";
  const Brick& b = a.bricks[size_t(brick)];
  return fmt::format("{} at ({}, {}, {})", b.type ? b.type->part : std::string("?"), b.min.x,
                     b.min.y, b.min.z);
}

}  // namespace

bool BuildOrder::all_stand() const {
  return std::all_of(steps.begin(), steps.end(),
                     [](const BuildStep& s) { return s.analysed && s.stands; });
}

int BuildOrder::certified_steps() const {
  return int(
      std::count_if(steps.begin(), steps.end(), [](const BuildStep& s) { return s.certified; }));
}

namespace {

// The analysed step with the smallest C_M among those that have one, or -1.
int weakest_solved_step(const std::vector<BuildStep>& steps) {
  int weakest = -1;
  for (int k = 0; k < int(steps.size()); ++k) {
    const BuildStep& s = steps[size_t(k)];
    if (s.analysed && s.status == physics::StabilityStatus::Solved &&
        (weakest < 0 || s.cm_gf < steps[size_t(weakest)].cm_gf))
      weakest = k;
  }
  return weakest;
}

}  // namespace

bool BuildOrder::weakest_is_a_bound() const {
  const int weakest = weakest_solved_step(steps);
  // A step with no number (no equilibrium) is weaker than any bound.
  return weakest >= 0 && steps[size_t(weakest)].certified &&
         steps[size_t(weakest)].cm_gf <= min_cm_gf();
}

double BuildOrder::min_cm_gf() const {
  double m = std::numeric_limits<double>::infinity();
  for (const BuildStep& s : steps)
    if (s.analysed)
      m = std::min(m, s.status == physics::StabilityStatus::Solved
                          ? s.cm_gf
                          : -std::numeric_limits<double>::infinity());
  return m;
}

namespace {

// A step as the order plans it: its new bricks, and whether it leaves some of the cursor's layer
// for the steps after it.
struct PlannedStep {
  std::vector<int> bricks;
  bool leaves_layer = false;
};

// What the order knows between steps: who holds whom, what is placed, and where the cursor is.
struct Planner {
  const Assembly& a;
  std::vector<std::vector<int>> snapped;  // per brick: the bricks it shares studs with
  std::vector<int> layer, layers;         // per brick its bottom (plates); the distinct ones
  std::vector<int> not_before;            // a brick held back waits for this layer
  std::vector<int> wait_for_step;         // and for this step (above the top layer)
  int steps = 0;                          // committed so far
  std::vector<char> placed, reachable;    // reachable: the ground or a placed brick holds it
  // Supports standing on the ground through supports alone: the columns built first.
  std::vector<char> grounded_support;
  // Per brick: its group of nearby bricks of its layer (nearby_groups.h), numbered layer by
  // layer from the ground up. Planned once for the whole layer, so that each group stays
  // compact whatever is placed before it.
  std::vector<int> group_of;
  int placed_count = 0;
  size_t cursor = 0;  // into layers
  int max_new = 0;    // bricks in one step at most (0: no limit)
  // The whole model's contacts, each step's taken from them (physics::steps_contacts), or none.
  std::shared_ptr<const physics::ContactGraph> model_contacts;

  Planner(const Assembly& assembly, physics::GroundMode ground, int max_new_bricks)
      : a(assembly), max_new(max_new_bricks) {
    const int n = int(a.bricks.size());
    snapped.resize(size_t(n));
    placed.assign(size_t(n), 0);
    reachable.assign(size_t(n), 0);
    const auto graph = physics::ContactGraph::connections(a, ground);
    std::vector<std::vector<int>> on;  // per brick: the supports snapped onto it from above
    on.resize(size_t(n));
    grounded_support.assign(size_t(n), 0);
    std::vector<int> rising;
    auto support = [&](int i) { return a.bricks[size_t(i)].support; };
    for (const physics::Contact& c : graph.contacts) {
      if (c.upper < 0) continue;
      if (c.lower == physics::kGround) {
        reachable[size_t(c.upper)] = 1;
        if (support(c.upper) && !grounded_support[size_t(c.upper)]) {
          grounded_support[size_t(c.upper)] = 1;
          rising.push_back(c.upper);
        }
      } else if (c.snap() || c.joint) {
        snapped[size_t(c.lower)].push_back(c.upper);
        snapped[size_t(c.upper)].push_back(c.lower);
        if (support(c.lower) && support(c.upper)) on[size_t(c.lower)].push_back(c.upper);
      }
    }
    while (!rising.empty()) {
      const int i = rising.back();
      rising.pop_back();
      for (int up : on[size_t(i)])
        if (!grounded_support[size_t(up)]) {
          grounded_support[size_t(up)] = 1;
          rising.push_back(up);
        }
    }
    for (int i = 0; i < n; ++i) {
      if (a.bricks[size_t(i)].fixed) reachable[size_t(i)] = 1;
      layer.push_back(a.bricks[size_t(i)].min.y);
    }
    layers = layer;
    std::sort(layers.begin(), layers.end());
    layers.erase(std::unique(layers.begin(), layers.end()), layers.end());
    not_before = layer;
    wait_for_step.assign(size_t(n), 0);
    group_of.assign(size_t(n), -1);
    std::map<int, std::vector<int>> of_layer;
    for (int i = 0; i < n; ++i) of_layer[layer[size_t(i)]].push_back(i);
    int groups = 0;
    for (const auto& [y, bricks] : of_layer)
      for (const auto& g : nearby_groups(a, bricks, max_new)) {
        for (int b : g) group_of[size_t(b)] = groups;
        ++groups;
      }
  }

  int size() const { return int(a.bricks.size()); }
  bool done() const { return placed_count == size(); }

  std::vector<int> take(int key) const {
    std::vector<int> fresh;
    for (int i = 0; i < size(); ++i)
      if (!placed[size_t(i)] && reachable[size_t(i)] &&
          std::max(layer[size_t(i)], not_before[size_t(i)]) <= key &&
          wait_for_step[size_t(i)] <= steps + 1)
        fresh.push_back(i);
    return fresh;
  }

  // The next step's bricks: everything held so far up to the cursor's layer (moving the cursor
  // up past layers with nothing to take), or a group of nearby ones of them.
  PlannedStep next() {
    std::vector<int> fresh = take(layers[cursor]);
    while (fresh.empty() && cursor + 1 < layers.size()) fresh = take(layers[++cursor]);
    if (fresh.empty())  // above the top layer: what hangs there
      fresh = take(std::numeric_limits<int>::max());
    if (fresh.empty()) {  // what nothing placed holds: one last step, reported floating
      for (int i = 0; i < size(); ++i)
        if (!placed[size_t(i)]) fresh.push_back(i);
      return {fresh, false};
    }
    // Of the cursor's layer, one group of nearby bricks at a time; the bricks of other layers
    // (held back, or hanging from a brick placed last) come along, as with whole layers, unless
    // the step would then pass max_new: then they come first, in a step of their own.
    const int at = layers[cursor];
    int first = std::numeric_limits<int>::max();
    std::vector<int> others;
    for (int b : fresh)
      if (layer[size_t(b)] == at)
        first = std::min(first, group_of[size_t(b)]);
      else
        others.push_back(b);
    std::vector<int> step;
    for (int b : fresh)
      if (layer[size_t(b)] != at || group_of[size_t(b)] == first) step.push_back(b);
    if (max_new > 0 && int(step.size()) > max_new && !others.empty()) {
      step = nearby_groups(a, others, max_new).front();
      std::sort(step.begin(), step.end());
    }
    return {step, step.size() < fresh.size()};
  }

  // `leaves_layer`: as next() planned the step.
  void commit(const std::vector<int>& fresh, bool leaves_layer) {
    for (int i : fresh) {
      placed[size_t(i)] = 1;
      for (int m : snapped[size_t(i)]) reachable[size_t(m)] = 1;
    }
    placed_count += int(fresh.size());
    ++steps;
    if (!leaves_layer && cursor + 1 < layers.size()) ++cursor;
  }

  std::optional<int> layer_above_cursor() const {
    auto it = std::upper_bound(layers.begin(), layers.end(), layers[cursor]);
    return it == layers.end() ? std::optional<int>() : std::optional<int>(*it);
  }
};

// One step's analysis: the model with `fresh` added to what is placed.
struct StepAnalysis {
  std::vector<int> fresh, whole_index;
  physics::StabilityResult result;
  physics::StepForces forces;  // for the next step to begin from
  BuildStep step;
  bool leaves_layer = false;  // as PlannedStep's
};

// A step's model and its system (physics::prepare_step), made while the step before it is
// decided: they owe nothing to that step's forces. `in`: the bricks it has.
struct PreparedStep {
  std::vector<char> in;
  Assembly partial;
  std::vector<int> whole_index;
  physics::StepSystem system;
};

// The bricks the model has after a step of `fresh` ones.
std::vector<char> placed_with(const Planner& p, const std::vector<int>& fresh) {
  std::vector<char> in = p.placed;
  for (int i : fresh) in[size_t(i)] = 1;
  return in;
}

PreparedStep prepare_step(const Assembly& a, std::vector<char> in, const BuildOrderOptions& options,
                          const physics::ContactGraph* model_contacts) {
  PreparedStep out;
  out.in = std::move(in);
  out.partial = partial_assembly(a, out.in, out.whole_index);
  if (options.analyse)
    out.system =
        physics::prepare_step(out.partial, out.whole_index, options.stability, model_contacts);
  return out;
}

// A step the LP solved while the steps before it were certified (plan_build_order), with the
// spread that the steps after it are certified from.
struct SolvedStep {
  PreparedStep prepared;  // its system moved into the analysis
  physics::StepStability analysis;
};

SolvedStep solve_step(const Assembly& a, std::vector<char> in, const BuildOrderOptions& options,
                      const physics::ContactGraph* model_contacts) {
  SolvedStep out;
  out.prepared = prepare_step(a, std::move(in), options, model_contacts);
  out.analysis = physics::solve_step(out.prepared.partial, std::move(out.prepared.system),
                                     options.stability, /*spread=*/true);
  return out;
}

// `prepared`: made ahead for a step planned as this one might be, used where it has the same
// bricks; `solved`: this step's own, solved ahead.
StepAnalysis analyse_step(const Planner& p, const physics::StepForces& built, PlannedStep planned,
                          const BuildOrderOptions& options,
                          std::optional<PreparedStep> prepared = std::nullopt,
                          std::optional<SolvedStep> solved = std::nullopt) {
  StepAnalysis out;
  out.leaves_layer = planned.leaves_layer;
  std::vector<int> fresh = std::move(planned.bricks);
  std::vector<char> in = placed_with(p, fresh);
  if (solved)
    prepared = std::move(solved->prepared);
  else if (!prepared || prepared->in != in)
    prepared = prepare_step(p.a, std::move(in), options, p.model_contacts.get());
  out.whole_index = std::move(prepared->whole_index);
  const Assembly& partial = prepared->partial;
  if (!options.analyse) {
    out.step.layer = p.layer[size_t(fresh.front())];
    for (int i : fresh) out.step.layer = std::min(out.step.layer, p.layer[size_t(i)]);
    out.step.new_bricks = int(fresh.size());
    out.step.bricks = int(partial.bricks.size());
    out.fresh = std::move(fresh);
    return out;
  }
  physics::StepStability analysed =
      solved ? std::move(solved->analysis)
             : physics::analyze_step(
                   partial, std::move(prepared->system), built, options.stability,
                   options.certify ? std::optional<double>(options.min_cm_gf) : std::nullopt);
  out.result = std::move(analysed.result);
  out.forces = std::move(analysed.forces);
  out.step.analysed = true;
  const auto& r = out.result;
  BuildStep& s = out.step;
  s.layer = p.layer[size_t(fresh.front())];
  for (int i : fresh) s.layer = std::min(s.layer, p.layer[size_t(i)]);
  s.new_bricks = int(fresh.size());
  s.bricks = int(partial.bricks.size());
  s.status = r.status;
  s.cm_gf = r.status == physics::StabilityStatus::Solved ? r.cm_gf() : 0;
  s.certified = r.certified;
  s.floating = int(r.connectivity.floating.size());
  s.stands = r.stable(options.min_cm_gf);
  if (!s.stands) {
    auto name = [&](int partial_brick) {
      if (partial_brick < 0) return std::string("the ground");
      const int b = out.whole_index[size_t(partial_brick)];
      return options.describe ? options.describe(b) : describe(p.a, b);
    };
    auto names = [&](const std::vector<int>& bricks) {
      std::vector<std::string> shown;
      for (size_t k = 0; k < std::min(bricks.size(), kPartsNamed); ++k)
        shown.push_back(name(bricks[k]));
      return named_few(shown, bricks.size());
    };
    auto falling = [&](const std::vector<int>& bricks) {
      for (int b : bricks)
        if (b >= 0) s.falling.push_back(out.whole_index[size_t(b)]);
    };
    if (s.floating > 0) {
      s.why = names(r.connectivity.floating) +
              (s.floating == 1 ? " reaches no ground" : " reach no ground");
      falling(r.connectivity.floating);
    } else if (r.status == physics::StabilityStatus::NoEquilibrium && !r.unbalanced.empty()) {
      s.why = names(r.unbalanced) + ": no forces hold it up (it tips or hangs)";
      falling(r.unbalanced);
    } else if (r.status != physics::StabilityStatus::Solved) {
      s.why = physics::to_string(r.status);
    } else if (!r.weakest.empty()) {
      s.why = fmt::format("C_M {:.3f} gf: {} holding {}", s.cm_gf, name(r.weakest.front().lower),
                          name(r.weakest.front().upper));
      falling({r.weakest.front().lower, r.weakest.front().upper});
    } else {
      s.why = fmt::format("C_M {:.3f} gf", s.cm_gf);
    }
  }
  out.fresh = std::move(fresh);
  return out;
}

// The new bricks that make a step fall: those no forces balance, else the ends of its weakest
// contacts, else (the weakest contact is between bricks placed before) what loads it.
std::vector<int> culprits_of(const Planner& p, const StepAnalysis& s) {
  std::vector<char> is_fresh(static_cast<size_t>(p.size()), 0);
  for (int i : s.fresh) is_fresh[size_t(i)] = 1;
  const auto& r = s.result;
  std::vector<int> out;
  auto consider = [&](int partial_brick) {
    if (partial_brick < 0) return;
    const int w = s.whole_index[size_t(partial_brick)];
    if (is_fresh[size_t(w)]) out.push_back(w);
  };
  for (int b : r.unbalanced) consider(b);
  for (size_t k = 0; k < std::min<size_t>(r.weakest.size(), 3) && out.empty(); ++k) {
    consider(r.weakest[k].upper);
    consider(r.weakest[k].lower);
  }
  // The weakest contact is between bricks placed before: hold back the new bricks nearest to its
  // upper brick through studs (what loads it most directly).
  if (out.empty() && !r.weakest.empty() && r.weakest.front().upper >= 0) {
    std::vector<int> distance(static_cast<size_t>(p.size()), -1);
    std::vector<int> queue{s.whole_index[size_t(r.weakest.front().upper)]};
    distance[size_t(queue.front())] = 0;
    for (size_t q = 0; q < queue.size() && out.empty(); ++q) {
      const int b = queue[q];
      for (int m : p.snapped[size_t(b)])
        if (distance[size_t(m)] < 0 && (p.placed[size_t(m)] || is_fresh[size_t(m)])) {
          distance[size_t(m)] = distance[size_t(b)] + 1;
          queue.push_back(m);
        }
      // Every brick at the nearest fresh distance.
      if (q + 1 == queue.size() || distance[size_t(queue[q + 1])] > distance[size_t(b)])
        for (int x : queue)
          if (is_fresh[size_t(x)] && distance[size_t(x)] <= distance[size_t(b)] + 1)
            out.push_back(x);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

namespace {

// The report gives the weakest step's C_M exactly (physics::solve_weakest_again); the smallest
// step C_M may remain a bound, and says so.
void solve_weakest_step_exactly(const Assembly& a, const BuildOrderOptions& options,
                                BuildOrder& order) {
  for (int solves = 0;; ++solves) {
    const int weakest = weakest_solved_step(order.steps);
    if (weakest < 0 || !order.steps[size_t(weakest)].certified) return;
    std::vector<physics::StepMargin> margins;
    for (const BuildStep& s : order.steps)
      if (s.analysed && s.status == physics::StabilityStatus::Solved)
        margins.push_back({s.cm_gf, s.certified});
    if (!physics::solve_weakest_again(margins, solves)) return;
    std::vector<char> in(a.bricks.size(), 0);
    for (size_t i = 0; i < a.bricks.size(); ++i) in[i] = order.step_of[i] <= weakest + 1;
    std::vector<int> whole_index;
    const auto r =
        physics::analyze_stability(partial_assembly(a, in, whole_index), options.stability);
    ++order.analyses;
    ++order.lp_solves;
    order.lp_seconds += r.stats.solve_seconds;
    BuildStep& s = order.steps[size_t(weakest)];
    s.status = r.status;
    s.cm_gf = r.status == physics::StabilityStatus::Solved ? r.cm_gf() : 0;
    s.certified = false;
    s.stands = r.stable(options.min_cm_gf);
    if (!s.stands) s.why = physics::to_string(r.status);
  }
}

// The model some steps after the last one, planned as if they stand, being solved by the LP.
struct SolvingAhead {
  std::vector<char> in;
  int bricks = 0;
  std::future<SolvedStep> solved;
};

// `steps` steps after p's last, in another thread when `in_parallel` (else when asked: the same
// result); none where p is done.
std::optional<SolvingAhead> solve_ahead(const Planner& p, int steps,
                                        const BuildOrderOptions& options, bool in_parallel) {
  Planner later = p;
  for (int k = 0; k < steps && !later.done(); ++k) {
    const PlannedStep planned = later.next();
    later.commit(planned.bricks, planned.leaves_layer);
  }
  if (later.placed_count == p.placed_count) return std::nullopt;
  SolvingAhead out;
  out.in = later.placed;
  out.bricks = later.placed_count;
  out.solved = std::async(in_parallel ? std::launch::async : std::launch::deferred,
                          [&a = p.a, in = out.in, &options, contacts = p.model_contacts]() mutable {
                            return solve_step(a, std::move(in), options, contacts.get());
                          });
  return out;
}

}  // namespace

// One loop of ~160 lines, for a reason: the planner, the forces the next step begins from, what
// is made and solved ahead, the best attempt at a falling step with the holding back that led to
// it, and the repairs so far are read and changed by every branch of it; the work of each branch
// is in functions already (Planner, analyse_step, solve_ahead, culprits_of,
// solve_weakest_step_exactly).
BuildOrder plan_build_order(const Assembly& a, const BuildOrderOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BuildOrder out;
  out.step_of.assign(a.bricks.size(), 0);
  if (a.bricks.empty()) return out;
  Planner p(a, options.stability.ground, options.max_new_bricks);
  // Each step's contacts taken from the whole model's: on the duck at height 40, 4.5 s of
  // searching its 228 step models -> 0.24 s (docs/performance.md, 2026-12-07).
  if (options.analyse) {
    std::vector<int> every_index;
    if (auto contacts = physics::steps_contacts(
            partial_assembly(a, std::vector<char>(a.bricks.size(), 1), every_index),
            options.stability))
      p.model_contacts = std::make_shared<const physics::ContactGraph>(std::move(*contacts));
  }

  // With the LP for every step, each step is analysed while the next one is, planned as if the
  // first stands (as it nearly always does): two analyses at a time, and the second thrown away
  // when the first needs repair. With certificates, one step at a time: a step's certificate
  // begins from the forces of the step before, and whether one is found decides whether the LP
  // is asked, and so the forces the next step begins from, which must not depend on --jobs. On
  // the duck at height 40, steps one at a time, the LP with two BLAS threads, took 106 s; two at
  // a time, the second's certificate sought again from the first's forces, 127 s.
  // Each step's model, contacts and system (3.9 s of the duck at height 40's 27 s) are made
  // while the step before is decided, planned as if it stands: its build order 27.4 -> 25.2 s.
  const bool side_by_side = options.side_by_side && !options.certify;
  const bool prepare_ahead = options.side_by_side && options.certify && options.analyse;
  std::optional<StepAnalysis> ahead;
  std::optional<PreparedStep> prepared;
  struct Attempt {
    StepAnalysis analysis;
    std::vector<int> not_before, wait_for_step;
  };
  std::optional<Attempt> best;
  int repairs = 0, falling_in_a_row = 0;
  // Forces that balance the last step: the next one's certificate begins from them (no part of
  // a plan: the planner is copied to plan ahead).
  physics::StepForces built;
  // The certificates' bounds fall from one LP's C_M to the share where a step asks the LP again
  // (step_stability.h) over 20 to 30 steps, each LP a second or two at height 40. So after a step
  // the LP solved, the model options.solve_ahead.steps steps on, planned as if they stand, is
  // solved in another thread while they are certified; the step that has exactly its bricks
  // takes it (where a step falls and is planned again, maybe none), and the steps after it
  // certify from its spread. With --jobs 1 it is solved when that step comes: the same order,
  // an LP more on the one thread. Not below options.solve_ahead.from_bricks: an LP there takes
  // a tenth of a second, and beside the certificates it slows them about as much (the bench's
  // globe, 580 bricks: 0.44 -> 0.52 s). Measured in docs/performance.md (2026-12-07).
  std::optional<SolvingAhead> solving;
  std::vector<std::future<SolvedStep>> abandoned;  // their destructors wait for them
  auto solved_for = [&](const PlannedStep& planned) -> std::optional<SolvedStep> {
    if (!solving || solving->in != placed_with(p, planned.bricks)) return std::nullopt;
    SolvedStep solved = solving->solved.get();
    solving.reset();
    ++out.solved_ahead;
    return solved;
  };
  // A step's bricks placed; `leaves_layer` keeps the cursor on its layer.
  auto place = [&](StepAnalysis& now, bool leaves_layer) {
    p.commit(now.fresh, leaves_layer);
    if (!now.forces.empty()) built = std::move(now.forces);
    for (int i : now.fresh) out.step_of[size_t(i)] = int(out.steps.size()) + 1;
    out.steps.push_back(now.step);
    if (options.progress)
      options.progress(int(out.steps.size()), p.placed_count, seconds_since(start));
  };
  // Supports (layout/supports.h) first, in steps of their own: columns that stand alone on the
  // ground, which the model is then built around and on, from the ground up, max_new_bricks at
  // most at a time. A column on the model (under an object the mesh leaves in the air,
  // layout/pieces.h) comes with its layer, as any brick.
  std::vector<int> supports;
  for (int i = 0; i < p.size(); ++i)
    if (p.grounded_support[size_t(i)]) supports.push_back(i);
  std::stable_sort(supports.begin(), supports.end(),
                   [&](int a, int b) { return p.layer[size_t(a)] < p.layer[size_t(b)]; });
  // An analysis run; those the LP decided with its time.
  auto count_analysis = [&](const StepAnalysis& s) {
    ++out.analyses;
    if (!s.step.analysed || s.result.certified || s.result.stats.solver.empty()) return;
    ++out.lp_solves;
    out.lp_seconds += s.result.stats.solve_seconds;
  };
  const size_t chunk = options.max_new_bricks > 0 ? size_t(options.max_new_bricks) : SIZE_MAX;
  for (size_t from = 0; from < supports.size(); from += chunk) {
    PlannedStep step;
    step.bricks.assign(supports.begin() + std::ptrdiff_t(from),
                       supports.begin() + std::ptrdiff_t(std::min(supports.size(), from + chunk)));
    StepAnalysis now = analyse_step(p, built, std::move(step), options);
    count_analysis(now);
    ++out.supports_steps;
    falling_in_a_row = now.step.stands ? 0 : falling_in_a_row + 1;
    place(now, /*leaves_layer=*/true);
  }
  while (!p.done()) {
    StepAnalysis now;
    if (ahead) {
      now = std::move(*ahead);
      ahead.reset();
    } else {
      PlannedStep planned = p.next();
      Planner after = p;
      after.commit(planned.bricks, planned.leaves_layer);
      std::optional<SolvedStep> solved = solved_for(planned);
      if (prepare_ahead && !after.done()) {
        std::future<PreparedStep> next =
            std::async(std::launch::async, [&a, in = placed_with(after, after.next().bricks),
                                            &options, contacts = p.model_contacts]() mutable {
              return prepare_step(a, std::move(in), options, contacts.get());
            });
        now = analyse_step(p, built, std::move(planned), options, std::move(prepared),
                           std::move(solved));
        prepared = next.get();
        count_analysis(now);
      } else if (after.done() || !options.analyse || !side_by_side) {
        now = analyse_step(p, built, std::move(planned), options, std::move(prepared),
                           std::move(solved));
        prepared.reset();
        count_analysis(now);
      } else {
        PlannedStep planned_after = after.next();
        std::thread second(
            [&] { ahead = analyse_step(after, built, std::move(planned_after), options); });
        now = analyse_step(p, built, std::move(planned), options);
        second.join();
        count_analysis(now);
        count_analysis(*ahead);
      }
    }
    if (now.step.analysed && !now.step.stands && now.step.floating == 0) {
      // The attempt with the largest C_M is kept, with the holding back that led to it.
      auto score = [](const StepAnalysis& x) {
        return x.step.status == physics::StabilityStatus::Solved
                   ? x.step.cm_gf
                   : -std::numeric_limits<double>::infinity();
      };
      if (!best || score(now) > score(best->analysis))
        best = Attempt{now, p.not_before, p.wait_for_step};
      std::vector<int> culprits;
      if (repairs < options.repairs_per_step && falling_in_a_row < kStopRepairingAfter)
        culprits = culprits_of(p, now);
      // Not every new brick: a step must place something.
      if (!culprits.empty() && culprits.size() < now.fresh.size()) {
        // Below the top layer a held-back brick waits for the layer above it; above it (a
        // cantilever built outwards), for the next step, after what the others bring.
        const auto above = p.layer_above_cursor();
        for (int c : culprits) {
          if (above) p.not_before[size_t(c)] = std::max(p.not_before[size_t(c)], *above);
          p.wait_for_step[size_t(c)] = p.steps + 2;
        }
        ++repairs;
        ahead.reset();  // planned on a step that will not be
        continue;
      }
      if (score(best->analysis) > score(now)) {
        now = std::move(best->analysis);
        p.not_before = std::move(best->not_before);
        p.wait_for_step = std::move(best->wait_for_step);
        ahead.reset();
      }
    }
    for (int i = 0; i < p.size(); ++i)
      out.held_back += p.wait_for_step[size_t(i)] == p.steps + 2 &&
                       std::find(now.fresh.begin(), now.fresh.end(), i) == now.fresh.end();
    falling_in_a_row = now.step.stands ? 0 : falling_in_a_row + 1;
    best.reset();
    repairs = 0;
    place(now, now.leaves_layer);
    if (solving && p.placed_count >= solving->bricks) {  // planned on steps that were not
      abandoned.push_back(std::move(solving->solved));
      solving.reset();
    }
    const bool by_lp = now.step.analysed && !now.step.certified &&
                       now.step.status == physics::StabilityStatus::Solved;
    if (options.certify && options.solve_ahead.steps > 0 && by_lp && !solving &&
        p.placed_count >= options.solve_ahead.from_bricks)
      solving = solve_ahead(p, options.solve_ahead.steps, options, prepare_ahead);
  }
  solve_weakest_step_exactly(a, options, out);
  out.seconds = seconds_since(start);
  return out;
}

std::vector<int> apply_build_order(Assembly& assembly, BuildOrder& order) {
  const int n = int(assembly.bricks.size());
  std::vector<int> perm(static_cast<size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  std::stable_sort(perm.begin(), perm.end(), [&](int x, int y) {
    return order.step_of[size_t(x)] < order.step_of[size_t(y)];
  });
  std::vector<int> new_index(static_cast<size_t>(n));
  std::vector<Brick> bricks;
  bricks.reserve(size_t(n));
  for (int k = 0; k < n; ++k) {
    new_index[size_t(perm[size_t(k)])] = k;
    bricks.push_back(assembly.bricks[size_t(perm[size_t(k)])]);
    bricks.back().source.step = order.step_of[size_t(perm[size_t(k)])];
  }
  assembly.bricks = std::move(bricks);
  for (ExternalLoad& load : assembly.loads)
    if (load.brick >= 0) load.brick = new_index[size_t(load.brick)];
  for (BuildStep& step : order.steps)
    for (int& b : step.falling) b = new_index[size_t(b)];
  return perm;
}

}  // namespace lego::layout
