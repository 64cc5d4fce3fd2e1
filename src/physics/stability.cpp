#include "physics/stability.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "core/in_order.h"
#include "core/stopwatch.h"
#include "physics/clp_lp.h"
#include "physics/equilibrium_blocks.h"
#include "physics/scaled_lp.h"
#include "physics/solved_blocks.h"
#include "physics/table.h"

namespace lego::physics {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Below this w (friction above 1000 T) we confirm that an equilibrium exists at all before
// trusting 1/w: an infeasible model shows up as w* = 0 up to the solver's tolerance.
constexpr double kConfirmBelow = 1e-3;
constexpr double kZeroScale = 1e-6;

void rank_weakest(const EquilibriumSystem& sys, const ContactGraph& g,
                  const std::vector<double>& duals, StabilityResult& r) {
  double largest = 0;
  for (int j = 0; j < sys.friction_columns; ++j) largest = std::max(largest, std::abs(duals[j]));
  if (largest <= 0) return;
  std::map<int, double> by_contact;
  double total = 0;
  for (int j = 0; j < sys.friction_columns; ++j) {
    double d = std::abs(duals[j]);
    if (d <= 1e-9 * largest) continue;
    by_contact[sys.contact[j]] += d;
    total += d;
  }
  for (auto [contact, sum] : by_contact)
    r.weakest.push_back({contact, g.contacts[size_t(contact)].lower,
                         g.contacts[size_t(contact)].upper, sum / total});
  // Shares equal to the solver's accuracy rank in contact order: an interior point solution
  // splits the duals evenly between symmetric contacts, and the last bits of the split depend
  // on how the BLAS summed (its thread count), which must not decide what comes first.
  auto key = [](const WeakContact& w) { return std::llround(w.share * 1e6); };
  std::stable_sort(r.weakest.begin(), r.weakest.end(),
                   [&](const WeakContact& a, const WeakContact& b) { return key(a) > key(b); });
}

// Whether any forces at all balance every body, friction unlimited; when none do, the bodies
// that cannot be held: min Σ|s| over A·x + s = b puts the smallest virtual force where the
// equations fail (weights in g·m/s², so a body needs one where s > 0).
// `max_seconds`: what is left of the analysis's time.
std::optional<std::vector<int>> unbalanced_bodies(const EquilibriumSystem& sys,
                                                  const StabilityOptions& o, double max_seconds) {
  auto make = [&](double bound) {
    LpData lp = equilibrium_lp(sys, kInfinity, 1.0 / kMaxFrictionLoad, bound);
    for (int r = 0; r < sys.rows; ++r)
      for (double sign : {1.0, -1.0}) lp.add_column(0, kInfinity, 1, {{r, sign}});
    return lp;
  };
  double scale = 1e-9;
  for (double b : sys.rhs) scale = std::max(scale, std::abs(b) / kMaxFrictionLoad);
  // The method judges its residual against the size of A·x, which the wide support box lets grow
  // far beyond the weights: on the corpus's mosque it stopped with equations off by a quarter of
  // the largest weight and called every body balanced, beside a scaled LP that had none. Off by
  // less than a tenth, the bodies it names are the ones (IslandHopper's resting flap: 0.08).
  auto balanced_enough = [&](const LpData& lp, const LpSolution& s) {
    if (s.outcome != LpOutcome::Optimal) return false;
    std::vector<double> residual(lp.row_lower);
    for (int j = 0; j < lp.columns(); ++j)
      for (int k = lp.start[size_t(j)]; k < lp.start[size_t(j) + 1]; ++k)
        residual[size_t(lp.index[size_t(k)])] -= lp.value[size_t(k)] * s.x[size_t(j)];
    double worst = 0;
    for (double r : residual) worst = std::max(worst, std::abs(r));
    return worst <= 0.1 * scale;
  };
  // A diagnosis, not the verdict: our method first, supports boxed as in the analysis and the box
  // widened while the answer touches it, a bounded number of iterations (the corpus's newspaper
  // office spent 13 s here with 120). Converged, it ends at the centre of the optimal face and
  // so names every body that some least virtual force holds: both of the Rolls-Royce's tiles in
  // the same plight. Boxed at 10⁶ from the start, the normal equations spanned eighteen orders
  // of magnitude and the directions stayed off by a twentieth of the residual: the carriage
  // house ran the 30 iterations with 2,194 conjugate gradient steps (2.7 s; at 10³, 17
  // iterations and 0.4 s), and the Rolls-Royce stopped short naming one tile (2026-12-01).
  // Where it stops short of balanced equations, Clp's primal simplex answers, within what is
  // left of the analysis's time (on the corpus our method answers every model, in 17
  // iterations at most). Primal, because the virtual forces make its first basis
  // feasible: the newspaper office took it 6,335 iterations, 2.5 s; the dual simplex 7,443.
  IpmOptions ipm;
  ipm.max_iterations = 30;
  StabilityOptions boxed = o;
  boxed.method = LpMethod::InteriorPoint;
  std::string unused;
  LpSolution s = solve_supports_boxed(make, boxed, unused, nullptr, false, ipm);
  const LpData lp = make(kInfinity);
  if (!balanced_enough(lp, s)) {
    s = solve_lp(lp, LpMethod::PrimalSimplex, true, true, max_seconds);
    if (!balanced_enough(lp, s)) return std::nullopt;
  }
  std::vector<int> bodies;
  for (int r = 0; r < sys.rows; ++r) {
    const size_t j = size_t(sys.columns() + 2 * r);
    if (s.x[j] + s.x[j + 1] > 1e-6 * scale &&
        (bodies.empty() || bodies.back() != EquilibriumSystem::body_of_row(r)))
      bodies.push_back(EquilibriumSystem::body_of_row(r));
  }
  return bodies;
}

}  // namespace

// With no equilibrium, the joints that turn and must not: the model analysed with them holding a
// moment about their axis as well, friction unlimited, the least total such moment (each column
// split by sign, priced 1), each structure with no equilibrium alone. None of a structure that
// does not stand even so: what fails there is elsewhere.
std::vector<std::pair<int, double>> turning_joints(const Assembly& a, const StabilityResult& r,
                                                   const StabilityOptions& o) {
  if (r.status != StabilityStatus::NoEquilibrium) return {};
  if (std::none_of(r.graph.shaft_joints.begin(), r.graph.shaft_joints.end(), [&](int k) {
        return r.graph.contacts[size_t(k)].joint_kind == Contact::Kind::Turns;
      }))
    return {};
  Formulation held = o.formulation;
  held.turning_joints_hold = true;
  const EquilibriumSystem whole = build_equilibrium(a, r.graph, r.connectivity, held);
  // Only the structures with no equilibrium, each alone: a town's standing buildings are no part
  // of it.
  std::vector<int> bodies;
  for (int brick : r.unbalanced)
    if (whole.body_of[size_t(brick)] >= 0) bodies.push_back(whole.body_of[size_t(brick)]);
  std::vector<EquilibriumBlock> structures;
  if (bodies.empty())
    structures.push_back({whole, {}, {}});
  else
    structures = structures_holding(whole, bodies);
  const auto start = std::chrono::steady_clock::now();
  std::map<int, double> by_contact;
  for (const EquilibriumBlock& structure : structures) {
    const EquilibriumSystem& sys = structure.system;
    if (sys.turning_columns.empty()) continue;  // nothing turns there: what fails is elsewhere
    LpData lp = equilibrium_lp(sys, kInfinity, 1.0, kInfinity);
    for (int j : sys.turning_columns) {
      lp.col_lower[size_t(j)] = 0, lp.objective[size_t(j)] = 1;
      std::vector<std::pair<int, double>> negated;
      for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k)
        negated.emplace_back(sys.row_index[size_t(k)], -sys.value[size_t(k)]);
      lp.add_column(0, kInfinity, 1, negated);
    }
    const LpSolution s = solve_lp(lp, LpMethod::DualSimplex, true, true,
                                  solve_seconds(o, seconds_left(start, o.max_seconds)));
    if (o.budget) o.budget->check(kSolve, size_t(s.iterations));
    if (s.outcome != LpOutcome::Optimal) continue;
    for (size_t t = 0; t < sys.turning_columns.size(); ++t) {
      const int j = sys.turning_columns[t];
      const double moment = s.x[size_t(j)] + s.x[size_t(sys.columns()) + t];
      if (moment > 1e-6) by_contact[sys.contact[size_t(j)]] += moment;
    }
  }
  std::vector<std::pair<int, double>> out(by_contact.begin(), by_contact.end());
  for (auto& [contact, moment] : out) moment *= kJointUnit;  // lever arms are in studs
  return out;
}

namespace {

// No equilibrium: `bodies` (EquilibriumSystem bodies, sorted) are those the diagnosis names.
void set_no_equilibrium(const EquilibriumSystem& sys, const std::vector<int>& bodies,
                        StabilityResult& r) {
  r.status = StabilityStatus::NoEquilibrium;
  r.message = "no force distribution balances every brick";
  for (int body : bodies) r.unbalanced.push_back(sys.brick_of_body[size_t(body)]);
}

void set_failure(StabilityResult& r, const LpSolution& s) {
  r.status = s.outcome == LpOutcome::IterationLimit ? StabilityStatus::IterationLimit
                                                    : StabilityStatus::NumericalTrouble;
  r.message = s.message;
}

void solve_scaled(const EquilibriumSystem& sys, const ContactGraph& graph,
                  const StabilityOptions& o, StabilityResult& r) {
  const auto start = std::chrono::steady_clock::now();
  auto at_cap = [&](const LpSolution& s, double cap) {
    return s.outcome == LpOutcome::Optimal && s.x[sys.columns()] >= cap * (1 - 1e-6);
  };
  // Where our method fails, the diagnosis runs before Clp's dual simplex would: bodies that no
  // forces balance, even with friction unlimited, are the answer (the corpus's newspaper office:
  // its dual simplex took 3.5 s to find w = 0, the diagnosis names the four parts in 0.3 s).
  // Run once at most: where it cannot answer (nullopt), asking again costs as much for nothing.
  std::optional<std::vector<int>> unbalanced;
  bool diagnosed = false;
  const auto explained = [&] {
    if (!diagnosed)
      unbalanced = unbalanced_bodies(sys, o, solve_seconds(o, seconds_left(start, o.max_seconds)));
    diagnosed = true;
    return unbalanced && !unbalanced->empty();
  };
  auto solve_capped = [&](double cap) {
    StabilityOptions staged = o;
    staged.support_bound = std::max(o.support_bound, cap);
    r.message.clear();
    return solve_supports_boxed([&](double bound) { return scaled_lp(sys, bound, cap); }, staged,
                                r.message, &r.stats, true, scale_objective_options(), explained);
  };
  // w is capped at 10³ first. A model that reaches that cap needs friction under T/1000: whether
  // it needs any is a small LP of its own, and only if it does is w sought up to kMaxScale, the
  // cap ten times higher at a time and the support box as wide as the cap (at the cap, forces
  // are w times the real ones over T). With the cap at 10⁶ from the start, models that need no
  // friction (most buildings) crawled for 80-240 iterations with steps of 10⁻³, their supports
  // pressed against a box a thousand times narrower than the forces at that scale; the corpus's
  // safe house took 242 iterations.
  LpSolution s = solve_capped(kFirstScale);
  if (at_cap(s, kFirstScale)) {
    r.message.clear();
    const LpSolution held =
        solve_supports_boxed([&](double bound) { return frictionless_lp(sys, bound); }, o,
                             r.message, &r.stats, true, scale_objective_options());
    if (held.outcome == LpOutcome::Optimal && held.x.back() >= 1 - 1e-6) {
      r.status = StabilityStatus::Solved;
      r.cm = kMaxFrictionLoad;  // no friction needed anywhere
      return;
    }
    for (double cap = 10 * kFirstScale;; cap = std::min(cap * 10, kMaxScale)) {
      s = solve_capped(cap);
      if (cap >= kMaxScale || !at_cap(s, cap)) break;
    }
  }
  if (s.outcome != LpOutcome::Optimal) {  // w = 0 is always feasible: the solver failed
    if (!unbalanced || unbalanced->empty()) return set_failure(r, s);
    set_no_equilibrium(sys, *unbalanced, r);
    r.message += fmt::format(
        " (our interior point method: {}; the diagnosis, friction unlimited, finds no forces "
        "that hold {})",
        s.message,
        r.unbalanced.size() == 1 ? "one part" : fmt::format("{} parts", r.unbalanced.size()));
    return;
  }
  const double w = s.x[sys.columns()];
  // At the cap, within the solver's tolerance: the difference from T is at most T/kMaxScale.
  if (at_cap(s, kMaxScale)) {
    r.status = StabilityStatus::Solved;
    r.cm = kMaxFrictionLoad;  // no friction needed anywhere
    return;
  }
  // A w at the solver's tolerance of zero is its word that nothing balances: a friction a
  // million times T is no equilibrium either, even where the diagnosis (friction unlimited)
  // balances every body with it (the corpus's mosque was such a model while a moment of
  // roundoff stood on a row no force reaches: force_model.cpp drops it now).
  if (w < kConfirmBelow && (explained() || w < kZeroScale))
    return set_no_equilibrium(sys, unbalanced ? *unbalanced : std::vector<int>{}, r);
  r.status = StabilityStatus::Solved;
  r.cm = kMaxFrictionLoad * (1 - 1 / w);
  r.forces.resize(size_t(sys.columns()));
  for (int j = 0; j < sys.columns(); ++j)
    r.forces[size_t(j)] = s.x[size_t(j)] * kMaxFrictionLoad / w;
  r.row_duals = std::move(s.row_dual);
  std::vector<double> duals(sys.friction_columns, 0.0);
  for (int j = 0; j < sys.friction_columns; ++j)
    if (s.x[j] > 1 - 1e-6) duals[j] = s.reduced_cost[j];
  rank_weakest(sys, graph, duals, r);
}

// C_M to a millionth of a gram-force, to rank structures by: identical structures solve to C_M
// that differ in their last bits with the BLAS's thread count, which must not decide which one
// is named weakest; equal ones rank in block order.
long long cm_rank(double cm) {
  const double millionths = std::clamp(cm / (1e-6 * kGravity), -9e18, 9e18);  // inf too
  return std::isnan(millionths) ? std::numeric_limits<long long>::max() : std::llround(millionths);
}

// Each block's outcome, weakest first, for the report (StabilityResult::blocks).
void ranked_blocks(const EquilibriumSystem& sys, const std::vector<EquilibriumBlock>& blocks,
                   const std::vector<StabilityResult>& parts, StabilityResult& r) {
  r.blocks.resize(blocks.size());
  std::vector<int> block_of_body(size_t(sys.rows / EquilibriumSystem::kEquations), -1);
  for (size_t k = 0; k < blocks.size(); ++k) {
    BlockOutcome& b = r.blocks[k];
    b.structures = blocks[k].structures;
    b.status = parts[k].status;
    b.cm = parts[k].cm;
    for (int row : blocks[k].rows)
      block_of_body[size_t(EquilibriumSystem::body_of_row(row))] = int(k);
  }
  for (size_t brick = 0; brick < sys.body_of.size(); ++brick)
    if (const int body = sys.body_of[brick]; body >= 0 && block_of_body[size_t(body)] >= 0)
      r.blocks[size_t(block_of_body[size_t(body)])].bricks.push_back(int(brick));
  auto rank = [](const BlockOutcome& b) {
    return b.status == StabilityStatus::NoEquilibrium ? 0
           : b.status == StabilityStatus::Solved      ? 2
                                                      : 1;
  };
  std::stable_sort(r.blocks.begin(), r.blocks.end(),
                   [&](const BlockOutcome& x, const BlockOutcome& y) {
                     if (rank(x) != rank(y)) return rank(x) < rank(y);
                     return rank(x) == 2 && cm_rank(x.cm) < cm_rank(y.cm);
                   });
}

// The blocks' outcomes as the model's (solve_scaled_by_blocks): the LP stats summed up to the
// first block left undecided, no equilibrium where any block has none (their bodies named
// together), else the weakest block's C_M, weakest contacts and duals, and every block's forces.
void combine_blocks(const EquilibriumSystem& sys, const std::vector<EquilibriumBlock>& blocks,
                    const std::vector<StabilityResult>& parts, StabilityResult& r) {
  for (size_t k = 0; k < blocks.size(); ++k) {
    const LpStats& s = parts[k].stats;
    r.stats.rows += s.rows;
    r.stats.columns += s.columns;
    r.stats.nonzeros += s.nonzeros;
    r.stats.iterations += s.iterations;
    if (r.stats.solver.empty() || s.solver != r.stats.solver) r.stats.solver = s.solver;
    if (!decided(parts[k].status) && parts[k].status != StabilityStatus::NoEquilibrium) break;
  }
  ranked_blocks(sys, blocks, parts, r);
  for (const StabilityResult& part : parts)
    if (part.status == StabilityStatus::NoEquilibrium) {
      if (r.status != StabilityStatus::NoEquilibrium) r.message = part.message;
      r.status = StabilityStatus::NoEquilibrium;
      r.unbalanced.insert(r.unbalanced.end(), part.unbalanced.begin(), part.unbalanced.end());
    }
  if (r.status == StabilityStatus::NoEquilibrium) {
    std::sort(r.unbalanced.begin(), r.unbalanced.end());
    return;
  }
  for (const StabilityResult& part : parts)
    if (part.status != StabilityStatus::Solved) {
      r.status =
          part.status == StabilityStatus::Empty ? StabilityStatus::NumericalTrouble : part.status;
      r.message = part.message;
      return;
    }
  size_t weakest = 0;
  for (size_t k = 1; k < parts.size(); ++k)
    if (cm_rank(parts[k].cm) < cm_rank(parts[weakest].cm)) weakest = k;
  r.status = StabilityStatus::Solved;
  r.cm = parts[weakest].cm;
  r.weakest = parts[weakest].weakest;
  // Forces for every column, or none: a block that needs no friction has none of its own.
  const bool all_forces = std::all_of(parts.begin(), parts.end(),
                                      [](const StabilityResult& p) { return !p.forces.empty(); });
  if (!all_forces) return;
  r.forces.assign(size_t(sys.columns()), 0);
  for (size_t k = 0; k < parts.size(); ++k)
    for (size_t j = 0; j < blocks[k].columns.size(); ++j)
      r.forces[size_t(blocks[k].columns[j])] = parts[k].forces[j];
  r.row_duals.assign(size_t(sys.rows), 0);
  const auto& duals = parts[weakest].row_duals;
  for (size_t i = 0; i < blocks[weakest].rows.size() && i < duals.size(); ++i)
    r.row_duals[size_t(blocks[weakest].rows[i])] = duals[i];
}

// The scaled LP of a block. Where our method fails on one that gathers several structures, each
// structure is solved alone: they share no force, so their answers together are the block's,
// and one structure's numerical trouble stays its own. Beside the airport lounge, the rocket
// sculpture's row that repeats others to its drawing's precision went unseen among the pair's
// rows: our method failed, and Clp's simplex found no equilibrium in the pair, while each alone
// is solved (71.658 and 71.526 gf).
void solve_scaled_gathered(const EquilibriumSystem& sys, const ContactGraph& graph,
                           const StabilityOptions& o, StabilityResult& r) {
  const auto start = std::chrono::steady_clock::now();
  solve_scaled(sys, graph, o, r);
  if (r.stats.solver != kClpAfterOurs) return;
  const std::vector<EquilibriumBlock> apart = independent_blocks(sys, 1);  // none: one structure
  if (apart.size() < 2) return;
  std::vector<StabilityResult> parts(apart.size());
  for (size_t k = 0; k < apart.size(); ++k) {
    StabilityOptions left = o;
    left.max_seconds = seconds_left(start, o.max_seconds);
    solve_scaled(apart[k].system, graph, left, parts[k]);
  }
  StabilityResult alone;
  combine_blocks(sys, apart, parts, alone);
  if (!decided(alone.status) && alone.status != StabilityStatus::NoEquilibrium) return;
  // The answer is the structures', in the block's terms; the block stays one in the model's list.
  r.status = alone.status;
  r.message = std::move(alone.message);
  r.cm = alone.cm;
  r.weakest = std::move(alone.weakest);
  r.unbalanced = std::move(alone.unbalanced);
  r.forces = std::move(alone.forces);
  r.row_duals = std::move(alone.row_duals);
  r.stats.iterations += alone.stats.iterations;
  r.stats.solver = alone.stats.solver;
  if (r.status == StabilityStatus::Solved)
    r.message = fmt::format(
        "our interior point method failed on {} structures gathered in one LP; solved one by one",
        apart.size());
}

// A block of this many bodies or more is worth a thread of its own (solve_scaled_by_blocks).
constexpr int kBodiesOfALargeBlock = 500;

// The scaled LP, one per independent block of the system (equilibrium_blocks.h): C_M is the
// least of the blocks', the weakest contacts and the duals are those of the block that has it,
// and the forces are every block's own. A block with no equilibrium leaves the model none, its
// bodies named with every other such block's; one the solver fails on fails the analysis.
void solve_scaled_by_blocks(const EquilibriumSystem& sys, const ContactGraph& graph,
                            const StabilityOptions& o, StabilityResult& r) {
  const std::vector<EquilibriumBlock> blocks = independent_blocks(sys, o.block_bodies);
  if (blocks.empty()) return solve_scaled_gathered(sys, graph, o, r);
  const auto start = std::chrono::steady_clock::now();
  std::vector<StabilityResult> parts(blocks.size());
  // A structure placed several times (a town's copies of one house) is solved once: its copies'
  // equations differ only in their last bits (SolvedBlocks::key_of), and they are found in the
  // store after the first is solved.
  SolvedBlocks own;
  SolvedBlocks& solved = o.solved_blocks ? *o.solved_blocks : own;
  std::vector<SolvedBlocks::Key> keys(blocks.size());
  std::vector<size_t> unsolved, copies;
  std::set<SolvedBlocks::Key> first;
  for (size_t k = 0; k < blocks.size(); ++k) {
    keys[k] = SolvedBlocks::key_of(blocks[k].system);
    if (auto before = solved.find(keys[k], blocks[k].system, graph))
      parts[k] = std::move(*before);
    else if (first.insert(keys[k]).second)
      unsolved.push_back(k);
    else
      copies.push_back(k);
  }
  std::atomic<bool> undecided{false};  // a block the solver could not decide: solve no more
  auto solve = [&](const std::vector<size_t>& which) {
    // Large blocks two at a time (the BLAS runs on one thread, normal_equations.cpp): measured
    // on a town of 30,000 parts, one BLAS thread alone already solves faster than two
    // (docs/scale.md), and the second core is then free for the next block.
    const auto large = std::count_if(which.begin(), which.end(), [&](size_t k) {
      return blocks[k].system.rows / EquilibriumSystem::kEquations >= kBodiesOfALargeBlock;
    });
    const int jobs = large >= 2 ? std::max(o.block_jobs, 1) : 1;
    run_in_order<StabilityResult>(
        which.size(), jobs,
        [&](size_t i) {
          StabilityResult part;
          if (undecided) return part;  // left Empty: reported after the undecided one before it
          StabilityOptions left = o;
          left.max_seconds = seconds_left(start, o.max_seconds);
          solve_scaled_gathered(blocks[which[i]].system, graph, left, part);
          if (!decided(part.status) && part.status != StabilityStatus::NoEquilibrium)
            undecided = true;
          return part;
        },
        [&](size_t i, StabilityResult&& part) {
          const size_t k = which[i];
          solved.store(keys[k], blocks[k].system, part);  // keeps only what was decided
          parts[k] = std::move(part);
        });
  };
  solve(unsolved);
  std::vector<size_t> left;  // copies of a block whose outcome was not kept
  for (size_t k : copies)
    if (auto found = solved.find(keys[k], blocks[k].system, graph))
      parts[k] = std::move(*found);
    else
      left.push_back(k);
  solve(left);
  combine_blocks(sys, blocks, parts, r);
}

void solve_max_min(const EquilibriumSystem& sys, const StabilityOptions& o, StabilityResult& r) {
  const auto start = std::chrono::steady_clock::now();
  LpData lp;
  const int f = sys.friction_columns;
  lp.rows = sys.rows + f;
  for (int j = 0; j < sys.columns(); ++j) {
    std::vector<std::pair<int, double>> entries;
    for (int k = sys.column_start[j]; k < sys.column_start[j + 1]; ++k)
      entries.emplace_back(sys.row_index[k], sys.value[k]);
    if (j < f) entries.emplace_back(sys.rows + j, 1.0);
    double lower = sys.kind[j] == ForceKind::Support ? -kInfinity : 0.0;
    lp.add_column(lower, kInfinity, 0, entries);
  }
  std::vector<std::pair<int, double>> t_entries;
  for (int j = 0; j < f; ++j) t_entries.emplace_back(sys.rows + j, 1.0);
  lp.add_column(-kInfinity, kMaxFrictionLoad, -1, t_entries);
  lp.row_lower = sys.rhs;
  lp.row_upper = sys.rhs;
  lp.row_lower.resize(lp.rows, -kInfinity);
  lp.row_upper.resize(lp.rows, kMaxFrictionLoad);
  r.stats.rows = lp.rows;
  r.stats.columns = lp.columns();
  r.stats.nonzeros = int(lp.index.size());
  // The reference form, kept for cross-checking: its t column is dense and its supports are
  // free, which our interior point method does not take; Clp solves it (dual simplex by default).
  const LpMethod method = o.method == LpMethod::InteriorPoint ? LpMethod::DualSimplex : o.method;
  LpSolution s = solve_lp(lp, method, o.presolve, o.scaling, solve_seconds(o, o.max_seconds));
  r.stats.iterations = s.iterations;
  if (s.outcome == LpOutcome::Infeasible)
    return set_no_equilibrium(
        sys,
        unbalanced_bodies(sys, o, solve_seconds(o, seconds_left(start, o.max_seconds)))
            .value_or(std::vector<int>{}),
        r);
  if (s.outcome != LpOutcome::Optimal) return set_failure(r, s);
  r.status = StabilityStatus::Solved;
  r.cm = s.x.back();
  rank_weakest(sys, r.graph, std::vector<double>(s.row_dual.begin() + sys.rows, s.row_dual.end()),
               r);
}

// Per-brick capacity from the minimum-norm friction distribution among those reaching C_M:
// min Σ f² is strictly convex in f, so the friction forces are unique and the heat map does not
// depend on the solver. Our interior point method solves it as it solves the C_M analysis (the
// quadratic term only adds to the diagonal its normal equations scale by), supports boxed and the
// box widened as there; Clp's QP (a primal simplex) solves it when the analysis is asked of Clp.
void brick_capacity(const Assembly& a, const EquilibriumSystem& sys, const StabilityOptions& o,
                    StabilityResult& r) {
  const int n = int(a.bricks.size());
  r.brick_capacity.assign(n, kMaxFrictionLoad);
  const double u = (kMaxFrictionLoad - r.cm) / kMaxFrictionLoad;  // max friction, in units of T
  if (u <= 0) return;
  // C_M is exact to 1e-6 of T, and so u is only to 1e-6, however small it is: a bound tighter
  // than that can leave no distribution at all, and Clp's QP then searches for minutes (the bench's
  // box with duplicated parts, 735 s once w's last digits moved). Even at 1e-6 a mutated
  // IslandHopper (C_M 71.599 gf, u = 8e-4; found by tools/fuzz.sh) took 95 s, at 1e-4 1.3 s: the
  // bound is u + 1e-4 (relative and in units of T), so a capacity is exact to 1e-4 T (0.007 gf),
  // far inside the heat map's colour bands.
  const double friction_box = u * (1 + 1e-4) + 1e-4;
  auto make = [&](double support_bound) {
    LpData lp = equilibrium_lp(sys, friction_box, 1.0 / kMaxFrictionLoad, support_bound);
    lp.quadratic_diagonal.assign(lp.columns(), 0.0);
    for (int j = 0; j < sys.friction_columns; ++j) lp.quadratic_diagonal[j] = 1.0;
    return lp;
  };
  // The objective is ½Σf² in units of T², well under 1: its gap is judged absolutely, to 1e-10.
  // A friction zero at the optimum with a zero multiplier (free to be zero) nears it only as the
  // square root of the gap: at the usual 1e-8, 1e-3 gf off on a hanging brick's columns, at
  // 1e-10 6e-5 gf. At 1e-12 the method failed near degenerate optima, on every figure-7 bridge.
  IpmOptions ipm;
  ipm.gap_scale = [](double) { return 1e-2; };
  // A capacity is exact to 1e-4 T (above), so the method may end at its best point once that is
  // within 1e-4, and stops when it no longer improves. On the corpus the normal equations lost
  // their accuracy near some optima (the cricket ground's residual stalled at 4e-6, the water
  // tower's at 4e-4 for 100 iterations).
  ipm.acceptable = 1e-4;
  ipm.patience = 15;
  // And it gets fewer iterations than an analysis (120). At most 50 while the normal equations
  // lost their accuracy near the optimum (the large office building: 65 iterations, 3,337
  // conjugate gradient steps, 7 times its analysis); with the proximal term (interior_point.cpp)
  // they keep it, and the office building converges steadily, at iteration 54 (305 CG steps,
  // 2.8 times its analysis, the same map).
  ipm.max_iterations = 80;
  // The analysis's forces reach C_M and balance the same equations: the QP starts there rather
  // than at its default start (normal forces at 1), moved inside the bounds by 0.003 of the
  // friction box and with the complementarity products at 0.01 of its square. The bench's solid
  // tower's map took 11 QP iterations instead of 25, a 7,073-brick solid block's 15 instead of 33;
  // the corpus's maps the same colours, 18.7 s in all instead of 27.5 s. Products at 0.1 or 0.001
  // of the square and margins of 0.01 or 0.03 of the box did about as well; products fixed at
  // 10⁻⁶ (the tower's box is 0.0029) failed on some of the paper's figure-7 bridges, whose C_M is
  // far below T and their box far wider.
  if (r.forces.size() == size_t(sys.columns())) {
    ipm.warm_start.x.resize(r.forces.size());
    for (size_t j = 0; j < r.forces.size(); ++j)
      ipm.warm_start.x[j] = r.forces[j] / kMaxFrictionLoad;
    ipm.warm_start.margin = 3e-3 * friction_box;
    ipm.warm_start.mu = 1e-2 * friction_box * friction_box;
  }
  std::string unused;
  LpStats qp;
  LpSolution s = solve_supports_boxed(make, o, unused, &qp, false, ipm);
  r.stats.capacity_iterations = qp.iterations;
  r.stats.capacity_solver =
      o.method == LpMethod::InteriorPoint ? method_name(LpMethod::InteriorPoint) : "Clp QP";
  auto capacity_from = [&](auto friction) {  // friction(j): column j's force, in g·m/s²
    for (int j = 0; j < sys.friction_columns; ++j) {
      int brick = r.graph.contacts[size_t(sys.contact[j])].upper;
      r.brick_capacity[brick] = std::min(r.brick_capacity[brick], kMaxFrictionLoad - friction(j));
    }
  };
  auto note = [&](const std::string& words) {
    r.message += (r.message.empty() ? "" : "; ") + ("per-brick capacity: " + words);
  };
  if (s.outcome == LpOutcome::Optimal)
    return capacity_from([&](int j) { return kMaxFrictionLoad * s.x[size_t(j)]; });
  // Where our method fails, the analysis's own forces are a distribution that reaches C_M too,
  // only not the least-norm one: shown, and said. Clp's QP is no fallback: on the corpus's models
  // where ours fails it took a minute to past five (its deadline unheeded), and then often gave
  // nothing (the fire company, the shopping centre).
  if (o.method == LpMethod::InteriorPoint && r.forces.size() == size_t(sys.columns())) {
    note(s.message + "; shown from the analysis's own forces, not the least-norm distribution");
    r.stats.capacity_solver = kCapacityFromAnalysis;
    return capacity_from([&](int j) { return r.forces[size_t(j)]; });
  }
  r.brick_capacity.clear();
  note("not computed: " + s.message);
}

}  // namespace

const char* to_string(StabilityStatus status) {
  switch (status) {
    case StabilityStatus::Solved:
      return "solved";
    case StabilityStatus::Empty:
      return "empty";
    case StabilityStatus::Floating:
      return "floating";
    case StabilityStatus::NoEquilibrium:
      return "no equilibrium";
    case StabilityStatus::IterationLimit:
      return "iteration limit";
    case StabilityStatus::NumericalTrouble:
      return "numerical trouble";
  }
  return "?";
}

bool decided(StabilityStatus status) {
  return status != StabilityStatus::IterationLimit && status != StabilityStatus::NumericalTrouble;
}

StabilityResult analyze_contacts(const Assembly& a, const StabilityOptions& o) {
  StabilityResult r;
  auto start = std::chrono::steady_clock::now();
  r.graph = ContactGraph::build(a, o.ground, o.assumed_joints, o.budget);
  r.connectivity = analyze_connectivity(int(a.bricks.size()), r.graph);
  // On the table under it: level at its lowest point unless what stands rests tilted on its
  // lowest points (physics/table.h). Given a ground (a build step's, the finished model's), as
  // given.
  if (!a.ground_height) {
    const Table table = settle_on_table(a, r.graph, r.connectivity);
    if (!table.level()) {
      Assembly tilted = a;
      tilted.ground_height = table.height;
      tilted.ground_slope = table.slope;
      r.graph = ContactGraph::build(tilted, o.ground, o.assumed_joints, o.budget);
      r.connectivity = analyze_connectivity(int(a.bricks.size()), r.graph);
    }
    // Held by the baseplate's knobs, it cannot tip however its weight lies.
    const bool anchored =
        std::any_of(r.graph.contacts.begin(), r.graph.contacts.end(),
                    [](const Contact& c) { return c.lower == kGround && c.snap(); });
    r.graph.tips_over = table.tips && !anchored;
  }
  r.stats.graph_seconds = seconds_since(start);
  return r;
}

EquilibriumSystem build_equilibrium(const Assembly& a, StabilityResult& r,
                                    const StabilityOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  EquilibriumSystem sys = build_equilibrium(a, r.graph, r.connectivity, o.formulation);
  r.stats.build_seconds = seconds_since(start);
  if (sys.rows == 0)  // nothing stands that is not the ground itself
    r.status = r.connectivity.floating.empty() ? StabilityStatus::Empty : StabilityStatus::Floating;
  return sys;
}

void solve_equilibrium(const Assembly& a, const EquilibriumSystem& sys, const StabilityOptions& o,
                       StabilityResult& r) {
  if (sys.rows == 0) return;
  auto start = std::chrono::steady_clock::now();
  if (o.form == LpForm::Scaled)
    solve_scaled_by_blocks(sys, r.graph, o, r);
  else
    solve_max_min(sys, o, r);
  r.stats.solve_seconds = seconds_since(start);
  if (o.diagnose_turning) r.turning = turning_joints(a, r, o);
  if (o.brick_capacity && r.status == StabilityStatus::Solved) {
    start = std::chrono::steady_clock::now();
    brick_capacity(a, sys, o, r);
    r.stats.capacity_seconds = seconds_since(start);
  }
}

StabilityResult analyze_stability(const Assembly& a, const StabilityOptions& o) {
  StabilityResult r = analyze_contacts(a, o);
  if (a.bricks.empty()) return r;
  const EquilibriumSystem sys = build_equilibrium(a, r, o);
  solve_equilibrium(a, sys, o, r);
  return r;
}

}  // namespace lego::physics
