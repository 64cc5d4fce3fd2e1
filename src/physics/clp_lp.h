#pragma once
// A thin layer over Clp: load column-major arrays, solve with the chosen method, and say
// honestly how it ended.
#include <memory>
#include <string>
#include <vector>

#include "physics/stability.h"

class ClpSimplex;

namespace lego::physics {

struct LpData {
  int rows = 0;
  std::vector<int> start{0}, index;  // column-major
  std::vector<double> value;
  std::vector<double> col_lower, col_upper, objective, row_lower, row_upper;
  std::vector<double> quadratic_diagonal;  // optional: ½ Σ q_j x_j² added to the objective

  int columns() const { return int(col_lower.size()); }
  // Appends a column; entries are (row, value) pairs.
  void add_column(double lower, double upper, double cost,
                  const std::vector<std::pair<int, double>>& entries);
};

enum class LpOutcome { Optimal, Infeasible, Unbounded, IterationLimit, Failed };

struct LpSolution {
  LpOutcome outcome = LpOutcome::Failed;
  double objective = 0;
  std::vector<double> x, reduced_cost, row_dual;
  int iterations = 0;
  std::string message;
};

// Minimizes objective·x (+ the quadratic part) subject to the bounds and rows.
LpSolution solve_lp(const LpData& lp, LpMethod method, bool presolve, bool scaling,
                    double max_seconds);

}  // namespace lego::physics
