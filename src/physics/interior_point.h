#pragma once
// A primal-dual interior point method (Mehrotra's predictor-corrector) for
//   min c·x + ½·Σ q_j·x_j²  s.t.  A·x = b,  l ≤ x ≤ u   (every l finite; u may be infinite; q ≥ 0)
// An LP when q is empty; a diagonal q adds itself to the diagonal the normal equations scale by,
// so a separable convex QP costs what the LP of the same matrix costs.
// with A sparse but for a few dense columns, which are kept out of the sparse normal equations
// A·Θ·Aᵀ (they would make it dense) and brought back as rank-one updates of its factor, with
// conjugate gradients on the true matrix (normal_equations.h). CHOLMOD factors them. Rows that
// depend on others are found and dropped first, and checked at the end.
#include <functional>
#include <string>
#include <vector>

#include "core/budget.h"

namespace lego::physics {

struct IpmProblem {
  int rows = 0;
  std::vector<int> start{0}, index;  // column-major
  std::vector<double> value;
  std::vector<double> c, b, lower, upper;
  std::vector<double> q;  // the quadratic term's diagonal, ≥ 0; empty for an LP
  // Rows come in blocks of this many, one per body (an equilibrium system's six): the normal
  // matrix's fill-reducing order is also sought on the bodies (normal_equations.h).
  int rows_per_body = 1;
  int columns() const { return int(c.size()); }
};

struct IpmResult {
  bool converged = false;
  int iterations = 0;
  std::vector<double> x, y;
  std::vector<double> z_lower, z_upper;  // bound multipliers (≥ 0)
  double objective = 0;
  std::string message;
};

struct IpmOptions {
  // Relative primal and dual residuals and duality gap. C_M = T·(1 − 1/w) inherits about a tenth
  // of w's relative error, so 1e-8 keeps C_M well inside the 1e-6 the analysis promises.
  double tolerance = 1e-8;
  int max_iterations = 120;
  // The worst relative residual or gap a run that could not reach its tolerance may still end at,
  // with its best point: C_M inherits about that relative error, inside the 1e-6 the analysis
  // promises.
  double acceptable = 1e-6;
  // Stop when the best point has not halved its worst residual or gap in this many iterations
  // (0: never); the run then ends as one that could not reach its tolerance.
  int patience = 0;
  // Where the columns without an upper bound start, above their lower bound (their multipliers
  // at the inverse). The scaled LP starts its normal forces higher (scale_objective_options).
  double unbounded_start = 1;
  // A point to start from instead (the solution of a nearby problem: the heat map's QP starts
  // from the analysis's forces): each x_j at least `margin` inside its bounds (a quarter of a
  // narrower box), its multipliers at mu over its slacks, so every complementarity product
  // starts at mu. Empty x: the default start above.
  struct WarmStart {
    std::vector<double> x;
    double margin = 0, mu = 0;
  };
  WarmStart warm_start;
  // What the duality gap is measured against, given the primal objective: 1 + |objective| when
  // empty. A caller that needs less of the objective than its own relative accuracy says so here.
  std::function<double(double objective)> gap_scale;
  // Checked at every iteration: stops with OutOfTime when spent.
  const Budget* budget = nullptr;
};

IpmResult solve_interior_point(const IpmProblem& problem, const IpmOptions& options = {});

}  // namespace lego::physics
