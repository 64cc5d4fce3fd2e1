#include "physics/scaled_lp.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lego::physics {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Our interior point method on an LP whose columns are all sparse but a few.
// True when a column boxed at ±bound sits on the box.
bool touches_box(const LpData& lp, const LpSolution& s, double bound) {
  for (int j = 0; j < lp.columns(); ++j)
    if (lp.col_lower[size_t(j)] == -bound && lp.col_upper[size_t(j)] == bound &&
        std::abs(s.x[size_t(j)]) >= bound * (1 - 1e-6))
      return true;
  return false;
}

}  // namespace

LpData equilibrium_lp(const EquilibriumSystem& sys, double friction_upper, double rhs_scale,
                      double support_bound) {
  LpData lp;
  lp.rows = sys.rows;
  lp.start = sys.column_start;
  lp.index = sys.row_index;
  lp.value = sys.value;
  for (int j = 0; j < sys.columns(); ++j) {
    switch (sys.kind[size_t(j)]) {
      case ForceKind::Friction:
        lp.col_lower.push_back(0), lp.col_upper.push_back(friction_upper);
        break;
      case ForceKind::Normal:
        lp.col_lower.push_back(0), lp.col_upper.push_back(kInfinity);
        break;
      case ForceKind::Support:
        lp.col_lower.push_back(-support_bound), lp.col_upper.push_back(support_bound);
        break;
    }
    lp.objective.push_back(0);
  }
  for (double b : sys.rhs) {
    lp.row_lower.push_back(b * rhs_scale);
    lp.row_upper.push_back(b * rhs_scale);
  }
  return lp;
}

namespace {

// The load −b/T as a column in [0, cap] priced −1: maximizing it is the scale of the load carried.
void add_load_column(LpData& lp, const EquilibriumSystem& sys, double cap) {
  std::vector<std::pair<int, double>> entries;
  for (int row = 0; row < sys.rows; ++row)
    if (sys.rhs[size_t(row)] != 0)
      entries.emplace_back(row, -sys.rhs[size_t(row)] / kMaxFrictionLoad);
  lp.add_column(0, cap, -1, entries);
}

}  // namespace

LpData scaled_lp(const EquilibriumSystem& sys, double support_bound, double cap) {
  LpData lp = equilibrium_lp(sys, 1.0, 0.0, support_bound);
  add_load_column(lp, sys, cap);
  return lp;
}

LpData frictionless_lp(const EquilibriumSystem& sys, double support_bound) {
  const LpData all = equilibrium_lp(sys, 1.0, 0.0, support_bound);
  LpData lp;
  lp.rows = all.rows;
  lp.row_lower = all.row_lower;
  lp.row_upper = all.row_upper;
  for (int j = sys.friction_columns; j < all.columns(); ++j) {
    std::vector<std::pair<int, double>> entries;
    for (int k = all.start[size_t(j)]; k < all.start[size_t(j) + 1]; ++k)
      entries.emplace_back(all.index[size_t(k)], all.value[size_t(k)]);
    lp.add_column(all.col_lower[size_t(j)], all.col_upper[size_t(j)], 0, entries);
  }
  add_load_column(lp, sys, 1);
  return lp;
}

LpSolution solve_interior(const LpData& lp, const IpmOptions& options) {
  IpmProblem p;
  p.rows = lp.rows;
  p.start = lp.start;
  p.index = lp.index;
  p.value = lp.value;
  p.c = lp.objective;
  p.b = lp.row_lower;
  p.lower = lp.col_lower;
  p.upper = lp.col_upper;
  p.q = lp.quadratic_diagonal;
  p.rows_per_body = EquilibriumSystem::kEquations;  // every LP here is an equilibrium system's
  IpmResult r = solve_interior_point(p, options);
  LpSolution s;
  s.iterations = r.iterations;
  s.message = r.message;
  if (!r.converged) return s;  // outcome: Failed
  s.outcome = LpOutcome::Optimal;
  s.objective = r.objective;
  s.x = std::move(r.x);
  s.row_dual = std::move(r.y);
  s.reduced_cost.resize(s.x.size());
  for (size_t j = 0; j < s.x.size(); ++j) s.reduced_cost[j] = r.z_lower[j] - r.z_upper[j];
  return s;
}

IpmOptions scale_objective_options() {
  IpmOptions options;
  // C_M = T·(1 − 1/w): a gap g on w moves C_M by about T·g/w², which is g/(w·(w − 1)) of C_M.
  // Measuring the gap against w·(w − 1) keeps C_M's relative error at the tolerance; stiff models
  // have w in the hundreds, and there the usual 1 + w asked for a gap a hundred times finer than
  // C_M needs: the last iterations, on a nearly singular normal matrix, could lose an answer
  // already reached (the crate sample, w = 551). At most ten times the usual measure, so w itself
  // stays within 1e-7 and the cap kMaxScale is still recognised.
  options.gap_scale = [](double objective) {
    const double w = std::abs(objective), usual = 1 + w;
    return std::clamp(w * (w - 1), usual, 10 * usual);
  };
  // The scaled LP is a cone: w = 0 with no forces is feasible. With its normal forces starting at
  // 1, below the pull of the friction points starting at half their limit, the first step
  // balanced them by shrinking w (the bench's solid 16 x 16 tower: w 1 -> 0.005, its optimum
  // 352), and the iterations that grew it back crawled: each asked the normal forces to grow
  // several times over and their multipliers to shrink as much, so the dual step was cut to
  // 10⁻²-10⁻³ (docs/stability-lp.md, 2026-12-02). Started at 1, 3, 5 and 10: the tower took 15,
  // 13, 12 and 11 iterations, a 7,073-brick solid block 25, 19, 17 and 15; the corpus's analyses
  // 1, 0.91, 0.91 and 0.93 of their iterations weighted by cost (large buildings fewer, small
  // vehicles a few more). The heat map's QP, no cone, keeps the default: at 10 the tower's map took
  // 26 iterations and 2.7 s against 25 and 2.2 s.
  options.unbounded_start = 10;
  return options;
}

const char* method_name(LpMethod method) {
  switch (method) {
    case LpMethod::InteriorPoint:
      return "interior point";
    case LpMethod::DualSimplex:
      return "Clp dual simplex";
    case LpMethod::PrimalSimplex:
      return "Clp primal simplex";
    case LpMethod::Barrier:
      return "Clp barrier";
    case LpMethod::BarrierNoCrossover:
      return "Clp barrier without crossover";
  }
  return "?";
}

// How much a box the answer touches is widened: ten times at a time. Widened a thousand times at
// once, the corpus's buildings (supports of a few hundred times a knob's friction in loops of
// contacts) were solved again in a box our method stalled in, then by Clp's simplex in seconds.
constexpr double kWiden = 10;

LpSolution solve_supports_boxed(const std::function<LpData(double bound)>& make,
                                const StabilityOptions& o, std::string& message, LpStats* stats,
                                bool simplex_fallback, const IpmOptions& ipm,
                                const std::function<bool()>& failure_explained) {
  // Support forces are free in the model. Bounding them lets the barrier converge in tens of
  // iterations instead of hundreds (the simplex is slower with them bounded, so it keeps them
  // free); a bound the solution touches is raised and the LP solved again.
  IpmOptions within_budget = ipm;
  within_budget.budget = o.budget;
  auto attempt = [&](LpMethod method, double first_bound) {
    LpSolution s;
    for (double bound = first_bound;; bound = bound < 1e12 ? bound * kWiden : kInfinity) {
      const LpData lp = make(bound);
      if (stats) {
        stats->rows = lp.rows;
        stats->columns = lp.columns();
        stats->nonzeros = int(lp.index.size());
      }
      s = method == LpMethod::InteriorPoint
              ? solve_interior(lp, within_budget)
              : solve_lp(lp, method, o.presolve, o.scaling, solve_seconds(o, o.max_seconds));
      if (stats) stats->iterations += s.iterations;
      // Clp stops at the budget's end as at its own limit: the run stops here, saying so.
      if (o.budget) o.budget->check(kSolve, size_t(s.iterations));
      if (s.outcome != LpOutcome::Optimal || std::isinf(bound) || !touches_box(lp, s, bound))
        return s;
    }
  };
  const bool interior = o.method == LpMethod::InteriorPoint || o.method == LpMethod::Barrier ||
                        o.method == LpMethod::BarrierNoCrossover;
  LpSolution s = attempt(o.method, interior ? o.support_bound : kInfinity);
  if (stats) stats->solver = method_name(o.method);
  if (simplex_fallback && o.method == LpMethod::InteriorPoint && s.outcome != LpOutcome::Optimal &&
      !(failure_explained && failure_explained())) {
    // Exact all the same: Clp's dual simplex takes over, and the result says so. (Starting
    // Clp's primal simplex from the interior point method's best point was slower still on the
    // corpus models where it fails.)
    message = s.message + "; solved by Clp's dual simplex instead";
    if (stats) stats->solver = kClpAfterOurs;
    s = attempt(LpMethod::DualSimplex, kInfinity);
  } else if (s.outcome == LpOutcome::Optimal && message.empty()) {
    message = s.message;  // how our method got there, when it did not reach its tolerance
  }
  return s;
}

}  // namespace lego::physics
