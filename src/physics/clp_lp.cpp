#include "physics/clp_lp.h"

#include <fmt/format.h>
#include <ClpEventHandler.hpp>
#include <ClpSimplex.hpp>
#include <ClpSolve.hpp>
#include <CoinPackedMatrix.hpp>
#include <algorithm>
#include <chrono>

namespace lego::physics {
namespace {

// Stops Clp at the end of an iteration past a deadline: setMaximumSeconds alone did not stop its
// simplex for quadratic objectives (the heat map's QP on a mutated IslandHopper ran 100 s under a
// limit of 60; found by tools/fuzz.sh). Its iterations there can be long (70 in those 100 s), so
// this bounds the time only as finely as they allow; the QP's bound (stability.cpp) did the rest.
class Deadline : public ClpEventHandler {
 public:
  explicit Deadline(double seconds)
      : end_(std::chrono::steady_clock::now() +
             std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                 std::chrono::duration<double>(std::min(seconds, 1e9)))) {}
  int event(Event which) override {
    return which == endOfIteration && std::chrono::steady_clock::now() > end_ ? 0 : -1;
  }
  ClpEventHandler* clone() const override { return new Deadline(*this); }

 private:
  std::chrono::steady_clock::time_point end_;
};

}  // namespace

void LpData::add_column(double lower, double upper, double cost,
                        const std::vector<std::pair<int, double>>& entries) {
  for (auto [row, v] : entries) {
    index.push_back(row);
    value.push_back(v);
  }
  start.push_back(int(index.size()));
  col_lower.push_back(lower);
  col_upper.push_back(upper);
  objective.push_back(cost);
}

LpSolution solve_lp(const LpData& lp, LpMethod method, bool presolve, bool scaling,
                    double max_seconds) {
  ClpSimplex model;
  model.setLogLevel(0);
  model.loadProblem(lp.columns(), lp.rows, lp.start.data(), lp.index.data(), lp.value.data(),
                    lp.col_lower.data(), lp.col_upper.data(), lp.objective.data(),
                    lp.row_lower.data(), lp.row_upper.data());
  if (!lp.quadratic_diagonal.empty()) {
    std::vector<int> start(lp.columns() + 1), index;
    std::vector<double> value;
    for (int j = 0; j < lp.columns(); ++j) {
      start[j] = int(index.size());
      if (lp.quadratic_diagonal[j] != 0) {
        index.push_back(j);
        value.push_back(lp.quadratic_diagonal[j]);
      }
    }
    start[lp.columns()] = int(index.size());
    model.loadQuadraticObjective(lp.columns(), start.data(), index.data(), value.data());
  }
  if (!scaling) model.scaling(0);
  model.setMaximumSeconds(max_seconds);
  Deadline deadline(max_seconds);
  model.passInEventHandler(&deadline);

  ClpSolve how;
  switch (method) {
    case LpMethod::InteriorPoint:  // ours, not Clp's: callers route it elsewhere
    case LpMethod::DualSimplex:
      how.setSolveType(ClpSolve::useDual);
      break;
    case LpMethod::PrimalSimplex:
      how.setSolveType(ClpSolve::usePrimal);
      break;
    case LpMethod::Barrier:
      how.setSolveType(ClpSolve::useBarrier);
      break;
    case LpMethod::BarrierNoCrossover:
      how.setSolveType(ClpSolve::useBarrierNoCross);
      break;
  }
  how.setPresolveType(presolve ? ClpSolve::presolveOn : ClpSolve::presolveOff);
  if (!lp.quadratic_diagonal.empty()) {
    model.primal();  // Clp's simplex for convex quadratic objectives
  } else {
    model.initialSolve(how);
  }

  LpSolution out;
  out.iterations = model.numberIterations();
  switch (model.status()) {
    case 0:
      out.outcome = LpOutcome::Optimal;
      break;
    case 1:
      out.outcome = LpOutcome::Infeasible;
      break;
    case 2:
      out.outcome = LpOutcome::Unbounded;
      break;
    case 3:
    case 5:  // stopped by the deadline
      out.outcome = LpOutcome::IterationLimit;
      break;
    default:
      out.outcome = LpOutcome::Failed;
      break;
  }
  // Clp may flag an "optimal" answer that still has infeasibilities after postsolve.
  if (out.outcome == LpOutcome::Optimal && model.isProvenOptimal() == false)
    out.outcome = LpOutcome::Failed;
  out.message = fmt::format("Clp status {} (secondary {}) after {} iterations", model.status(),
                            model.secondaryStatus(), out.iterations);
  out.objective = model.objectiveValue();
  const int n = lp.columns();
  out.x.assign(model.primalColumnSolution(), model.primalColumnSolution() + n);
  out.reduced_cost.assign(model.dualColumnSolution(), model.dualColumnSolution() + n);
  out.row_dual.assign(model.dualRowSolution(), model.dualRowSolution() + lp.rows);
  return out;
}

}  // namespace lego::physics
