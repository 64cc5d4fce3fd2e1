#include "physics/interior_point.h"

#include <fmt/format.h>
#include <malloc.h>
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <mutex>

#include "core/stopwatch.h"
#include "physics/normal_equations.h"

namespace lego::physics {
namespace {

using Vec = Eigen::VectorXd;
using SpMat = SparseMatrix;

// The normal matrix's shift, relative to its diagonal (see where it is factored).
constexpr double kRegularization = 1e-14;

// A proximal term ρ/2·|x − x_k|² in each Newton system (primal regularization, as in Altman and
// Gondzio's regularized interior point methods): Θ stays below 1/ρ. Without it, the columns that
// end strictly inside their bounds with no cost (normal forces, supports: a statically
// indeterminate model has many) had Θ = x/z growing without limit, the normal equations lost the
// accuracy the conjugate gradients could restore, and the primal residual grew from 4e-5 to 6e-4
// in the last twenty iterations of the heat map's QP on a 2,116-brick hollow box (50 iterations,
// 464 CG steps, 3.1 s; with ρ = 1e-9, 1.1 s). The residuals and the gap are those of the problem
// itself, so the answer is the same: only the directions change. Measured on 2026-12-01: 1e-10 to
// 1e-8 do as well; at 1e-7 the corpus's hospital took 115 iterations instead of 70, at 1e-6 it
// failed at 120 (forces in units of T, w up to 10⁶).
constexpr double kProximal = 1e-9;

// How far the conjugate gradients solve each Newton direction, relative to its right-hand side.
// The step taken is the corrector's: to 1e-10, measured against 1e-13 (needed while the shift
// was 1e-12), the same iterations everywhere and a third fewer CG steps (tower-2000 99 -> 62,
// box-2000 52 -> 32, the crate sample 20 -> 10). The predictor only sets σ and the corrector's
// second-order term: to 1e-6 it cost half the CG steps (tower-2000 62 -> 34) with the same
// iterations on the towers, boxes and samples up to 2,000 bricks (box-8000 one more, 25). Since
// the dense column is a product-form update, a first solve often meets 1e-6 without CG, and
// that coarser predictor cost the globe sample 16 iterations instead of 13; 1e-7 and 1e-8 give
// 13 (tower-2000 31 and 38 CG steps, box-2000 13 and 21). 1e-8, for the margin.
constexpr double kCorrectorAccuracy = 1e-10, kPredictorAccuracy = 1e-8;
// Iterations with μ negligible before the method stops with its best point.
constexpr int kStalledIterations = 6;

// Rows are suspected of depending on others when a pivot of A·Aᵀ is below this fraction of its
// diagonal entry; dependent_rows() then decides, at its own finer threshold and in its own order.
constexpr double kSuspectPivot = 1e-6;

double max_step(const Vec& v, const Vec& dv) {
  double alpha = 1.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (dv[i] < 0) alpha = std::min(alpha, -v[i] / dv[i]);
  return alpha;
}

// The columns of p on the rows that row_map sends somewhere (−1: left out), renumbered by it.
SpMat restrict_rows(const IpmProblem& p, const std::vector<int>& row_map, int rows) {
  return renumber_rows(rows, p.columns(), p.start.data(), p.index.data(), p.value.data(), row_map);
}

// The products with A, as plain loops over its columns: A is stored by column, so A·x scatters
// into the short vector of rows and Aᵀ·y is a dot product per column (through a stored Aᵀ it
// scattered into the long vector of columns). A third of the instructions of Eigen's generic
// sparse products, and A·Θ·Aᵀ·v reads A once instead of twice.
double column_dot(const SpMat& A, Eigen::Index j, const Vec& y) {  // A(:, j)ᵀ·y
  const int* row = A.innerIndexPtr();
  const double* value = A.valuePtr();
  double sum = 0;
  for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k) sum += value[k] * y[row[k]];
  return sum;
}

void add_column(const SpMat& A, Eigen::Index j, double s, Vec& y) {  // y += s·A(:, j)
  const int* row = A.innerIndexPtr();
  const double* value = A.valuePtr();
  for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k) y[row[k]] += value[k] * s;
}

Vec times(const SpMat& A, const Vec& x) {
  Vec y = Vec::Zero(A.rows());
  for (Eigen::Index j = 0; j < A.cols(); ++j) add_column(A, j, x[j], y);
  return y;
}

Vec transpose_times(const SpMat& A, const Vec& y) {
  Vec x(A.cols());
  for (Eigen::Index j = 0; j < A.cols(); ++j) x[j] = column_dot(A, j, y);
  return x;
}

Vec normal_times(const SpMat& A, const Vec& theta, const Vec& v) {  // A·Θ·Aᵀ·v
  Vec y = Vec::Zero(A.rows());
  for (Eigen::Index j = 0; j < A.cols(); ++j) add_column(A, j, theta[j] * column_dot(A, j, v), y);
  return y;
}

// Each iteration allocates and frees vectors as long as the rows or the columns (hundreds of
// kilobytes). glibc hands blocks that large back to the kernel when they are freed (as mappings
// of their own, or by trimming the heap), so every iteration faulted the same pages in again:
// 52,759 page faults in one box-2000 analysis. Kept in the heap, they are reused.
void keep_freed_memory() {
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
  });
}

}  // namespace

// One function of ~380 lines, for a reason: Mehrotra's iteration keeps about twenty vectors (the
// point, its slacks and multipliers, the residuals, the directions of the predictor and the
// corrector, the best point so far) that every step reads and writes, and the attempt without the
// dependent rows runs the same iteration again. The linear algebra it calls is in
// normal_equations.h; what is left here is the method as the literature writes it, in one place.
IpmResult solve_interior_point(const IpmProblem& p, const IpmOptions& options) {
  const auto entry = std::chrono::steady_clock::now();
  keep_freed_memory();
  IpmResult result;
  const int n = p.columns();
  // Empty rows carry no equation (their b must be zero); rows that repeat others of their block
  // add nothing. Both would make the normal matrix singular, so neither is solved for.
  std::vector<char> used(p.rows, 0);
  for (int j = 0; j < n; ++j)
    for (int k = p.start[j]; k < p.start[j + 1]; ++k)
      if (p.value[k] != 0) used[p.index[k]] = 1;
  for (int r = 0; r < p.rows; ++r)
    if (!used[r] && p.b[r] != 0) {
      result.message = "an equation without variables has a non-zero right-hand side";
      return result;
    }
  std::vector<int> used_row_map(p.rows, -1);
  int m = 0;
  for (int r = 0; r < p.rows; ++r)
    if (used[r]) used_row_map[r] = m++;
  const SpMat A_used = restrict_rows(p, used_row_map, m);
  // Dense columns (the scale w of the stability LP touches every loaded row) stay out of the
  // sparse matrix CHOLMOD factors: A·Θ·Aᵀ would be dense. Each is a rank-one update of that factor
  // (NormalFactor), and the conjugate gradients below run on the true matrix.
  std::vector<int> dense;
  {
    const double average = double(A_used.nonZeros()) / std::max(n, 1);
    for (int j = 0; j < n; ++j)
      if (A_used.col(j).nonZeros() > std::max(64.0, 20 * average)) dense.push_back(j);
  }
  auto without_dense = [&](const SpMat& full) {
    SpMat sparse = full;
    for (int j : dense)
      for (SpMat::InnerIterator it(sparse, j); it; ++it) it.valueRef() = 0;
    sparse.prune(0.0);
    return sparse;
  };
  // LEGO_IPM_TRACE=1 prints each iteration on stderr: residuals, steps, time to form and factor.
  const bool trace = std::getenv("LEGO_IPM_TRACE") != nullptr;
  const int m_used = m;
  // Rows that depend on others make A·Θ·Aᵀ singular. They are rare (a sub-assembly hanging on a
  // single contact), so the first attempt keeps every row and reads the pivots of A·Aᵀ in the
  // method's order: a small one makes such rows suspect, and only then are they found properly
  // and dropped (the solution is checked against them at the end).
  enum class Outcome { Done, DependentRows };
  auto attempt = [&](const std::vector<char>& dependent, bool watch_pivots) -> Outcome {
    std::vector<int> row_map(size_t(p.rows), -1);
    int m = 0;
    for (int r = 0; r < p.rows; ++r)
      if (used_row_map[r] >= 0 && !dependent[used_row_map[r]]) row_map[r] = m++;
    if (trace) fmt::print(stderr, "rows {}, {} with variables, {} kept\n", p.rows, m_used, m);
    const SpMat A = m == m_used ? A_used : restrict_rows(p, row_map, m);
    const SpMat A_abs = A.cwiseAbs();
    const SpMat A_sparse = without_dense(A);
    std::vector<int> body;
    if (p.rows_per_body > 1)
      for (int r = 0; r < p.rows; ++r)
        if (row_map[r] >= 0) body.push_back(r / p.rows_per_body);
    const auto ordering = std::chrono::steady_clock::now();
    const RowOrder row_order = fill_reducing_order(A_sparse, body);
    if (trace)
      fmt::print(stderr, "order: {}, factor {:.3g} entries, {:.3g} flops, {:.3f} s\n",
                 row_order.method, row_order.entries, row_order.flops, seconds_since(ordering));
    const std::vector<int>& order = row_order.rows;
    NormalMatrix normal(A_sparse, order);
    Eigen::MatrixXd A_dense(m, Eigen::Index(dense.size()));
    for (size_t k = 0; k < dense.size(); ++k) A_dense.col(Eigen::Index(k)) = A.col(dense[k]);
    Vec b(m), c = Eigen::Map<const Vec>(p.c.data(), n);
    const bool quadratic = !p.q.empty();
    const Vec q = quadratic ? Vec(Eigen::Map<const Vec>(p.q.data(), n)) : Vec::Zero(n);
    for (int r = 0; r < p.rows; ++r)
      if (row_map[r] >= 0) b[row_map[r]] = p.b[r];

    const Vec lo = Eigen::Map<const Vec>(p.lower.data(), n),
              up = Eigen::Map<const Vec>(p.upper.data(), n);
    Vec has_up(n);
    for (int j = 0; j < n; ++j) has_up[j] = std::isfinite(up[j]) ? 1.0 : 0.0;
    // Start inside the bounds, near zero: the middle of a narrow box, else zero moved at least a
    // unit inside a box (a wide box's middle can be absurdly far from any solution), and columns
    // without an upper bound options.unbounded_start above their lower bound.
    Vec x(n), y = Vec::Zero(m);
    for (int j = 0; j < n; ++j)
      x[j] = !has_up[j]           ? std::max(0.0, lo[j] + options.unbounded_start)
             : up[j] - lo[j] <= 2 ? 0.5 * (lo[j] + up[j])
                                  : std::clamp(0.0, lo[j] + 1, up[j] - 1);
    // The distances to the bounds are carried as variables of their own, moved by the same steps
    // as x: recomputed as u − x they would cancel to exactly zero for x → u.
    Vec xl = x - lo, xu = Vec::Ones(n);
    for (int j = 0; j < n; ++j)
      if (has_up[j]) xu[j] = up[j] - x[j];
    // Multipliers start at 1/slack, so every complementarity product starts at 1: a centred start.
    // (At 1 they made the products of the wide support boxes 10³ and cost a dozen iterations.)
    Vec zl = xl.cwiseInverse(), zu = xu.cwiseInverse().cwiseProduct(has_up);
    if (const IpmOptions::WarmStart& warm = options.warm_start; warm.x.size() == size_t(n)) {
      for (int j = 0; j < n; ++j) {
        const double margin =
            has_up[j] ? std::min(warm.margin, 0.25 * (up[j] - lo[j])) : warm.margin;
        x[j] = std::max(warm.x[size_t(j)], lo[j] + margin);
        if (has_up[j]) x[j] = std::min(x[j], up[j] - margin);
        xl[j] = x[j] - lo[j];
        zl[j] = warm.mu / xl[j];
        if (has_up[j]) xu[j] = up[j] - x[j], zu[j] = warm.mu / xu[j];
      }
    }

    // CHOLMOD's supernodal factorization: measured faster than Eigen's simplicial one at every size
    // from 500 bricks up (0.67 s against 0.92 s for a whole solve at 516 bricks, 1.5 s against 3.0
    // s at 1,000); the same at 200.
    NormalFactor factor(order);
    bool analysed = false;
    const double b_norm = 1 + b.lpNorm<Eigen::Infinity>(), c_norm = 1 + c.lpNorm<Eigen::Infinity>();
    const int bounds = n + int(has_up.sum());

    long cg_steps = 0, factorizations = 0;
    double factor_seconds = 0, solve_seconds = 0;  // for the trace
    if (trace) fmt::print(stderr, "setup {:.3f}s\n", seconds_since(entry));
    // The best point so far: on degenerate models the linear algebra can lose its accuracy near
    // the optimum (the normal matrix nearly singular), and the residual then only grows.
    double best_worst = std::numeric_limits<double>::infinity();
    int stalled_iterations = 0;
    double last_halved = best_worst;  // for options.patience
    int halved_at = 0;
    struct Point {
      Vec x, y, zl, zu;
    } best{x, y, zl, zu};
    for (int it = 0; it < options.max_iterations; ++it) {
      if (options.budget) options.budget->check(kSolve, size_t(it), size_t(options.max_iterations));
      result.iterations = it;
      Vec rp = b - times(A, x);
      const Vec qx = q.cwiseProduct(x);
      Vec rd = c + qx - transpose_times(A, y) - zl + zu.cwiseProduct(has_up);
      double gap_sum = xl.dot(zl) + xu.cwiseProduct(has_up).dot(zu);
      double mu = gap_sum / bounds;
      const double half_xqx = 0.5 * x.dot(qx);
      double primal_obj = c.dot(x) + half_xqx;
      double dual_obj = b.dot(y) + lo.dot(zl) - half_xqx;
      for (int j = 0; j < n; ++j)
        if (has_up[j]) dual_obj -= up[j] * zu[j];
      if (!std::isfinite(mu) || !std::isfinite(rp.squaredNorm())) {
        result.message = fmt::format("the interior point method broke down at iteration {}", it);
        break;
      }
      // Residuals relative to the size of what they balance: here b is often zero, while the
      // terms of A·x are not.
      const double primal_scale =
          std::max(b_norm, 1 + times(A_abs, x.cwiseAbs()).lpNorm<Eigen::Infinity>());
      const double gap_scale =
          options.gap_scale ? options.gap_scale(primal_obj) : 1 + std::abs(primal_obj);
      const double worst = std::max({rp.lpNorm<Eigen::Infinity>() / primal_scale,
                                     rd.lpNorm<Eigen::Infinity>() / c_norm,
                                     std::abs(primal_obj - dual_obj) / gap_scale});
      // Once μ is negligible the iterates only jitter at the level of the linear algebra's
      // roundoff: accept ten times the tolerance then rather than wander until the limit.
      const bool stalled = mu < 1e-14 * (1 + std::abs(primal_obj));
      if (worst < options.tolerance || (stalled && worst < 10 * options.tolerance)) {
        result.converged = true;
        break;
      }
      // Nor do more of them help: the corpus's Thomas house reached its optimum at iteration 11
      // and jittered until the limit, μ at 1e-253, its residual where the rows' near dependence
      // left it.
      stalled_iterations = stalled ? stalled_iterations + 1 : 0;
      if (stalled_iterations > kStalledIterations) {
        result.message =
            fmt::format("μ vanished at iteration {} with the residuals at {:.1e}", it, best_worst);
        break;
      }
      if (worst < best_worst) {
        best_worst = worst;
        best = {x, y, zl, zu};
      }
      if (worst < 0.5 * last_halved) last_halved = worst, halved_at = it;
      if (options.patience > 0 && it - halved_at > options.patience) {
        result.message = fmt::format("no progress for {} iterations, at iteration {} ({:.1e})",
                                     options.patience, it, best_worst);
        break;
      }
      // Directions this inexact no longer lead anywhere: the residual only grows from here.
      if (rp.lpNorm<Eigen::Infinity>() / primal_scale >
              1e4 * std::max(best_worst, options.tolerance) &&
          best_worst < 1e-2) {
        result.message = fmt::format(
            "the interior point method lost accuracy at iteration {} (best relative residual and "
            "gap {:.1e})",
            it, best_worst);
        if (trace) fmt::print(stderr, "{}\n", result.message);
        break;
      }
      // Θ = (q + ρ + zl/xl + zu/xu)⁻¹ and the normal matrix A·Θ·Aᵀ + δI.
      if (trace)
        fmt::print(stderr, "it {:3} mu {:.3e} rp {:.3e} rd {:.3e} pobj {:.9e} dobj {:.9e}\n", it,
                   mu, rp.lpNorm<Eigen::Infinity>(), rd.lpNorm<Eigen::Infinity>(), primal_obj,
                   dual_obj);
      Vec theta(n);
      for (int j = 0; j < n; ++j)
        theta[j] = 1.0 / (q[j] + kProximal + zl[j] / xl[j] + (has_up[j] ? zu[j] / xu[j] : 0.0));
      if (!analysed) {
        const auto t = std::chrono::steady_clock::now();
        factor.analyse(normal.form(theta, 0.0));
        analysed = true;
        if (trace) fmt::print(stderr, "    analyse {:.3f}s\n", seconds_since(t));
      }
      if (watch_pivots && it == 0) {
        // Rows that depend on others, suspected on A·Aᵀ itself: a pivot's ratio to its diagonal
        // entry does not change when a row is scaled, but it does when the columns are weighted.
        // Suspected on A·Θ·Aᵀ, the corpus's airport sculpture (a row that repeats others to
        // 1e-5, the precision of its turned parts' coordinates) was caught with the normal forces
        // starting at 4, missed at 5, and then our method and Clp's simplex found no equilibrium
        // on that inconsistency (2026-12-02). One factorization more per analysis.
        // The shift moves the diagonal the pivots are measured against by 1e-14 of itself.
        const SpMat& M = normal.form(Vec::Ones(n), kRegularization);
        ++factorizations;
        if (factor.factorize(M, A_dense, Vec::Ones(Eigen::Index(dense.size())))) {
          const Vec pivots = factor.pivots();
          for (Eigen::Index r = 0; r < m; ++r)
            if (pivots[r] < kSuspectPivot * M.coeff(r, r)) return Outcome::DependentRows;
        }
      }
      // The equations are often dependent (a brick held at one point has a torque row that
      // repeats its force rows), so A·Θ·Aᵀ is only semi-definite. Regularize each row relative to
      // its own diagonal (the diagonal spans many orders of magnitude near the optimum); the
      // conjugate gradients below remove the perturbation. With dependent rows dropped the
      // matrix is still near-singular at degenerate optima, which is why CG and not plain
      // refinement. The shift is the preconditioner's main error, not roundoff: at 1e-12 a
      // 2,244-brick tower's first residual was 2e-5, at 1e-14 it is 1e-7 (173 CG steps -> 99;
      // the crate sample 486 -> 72). Larger ε costs CG steps; 1e-13 to 1e-15 all converge with
      // the gap judged as the scaled LP asks (scale_objective_options); without it the crate
      // sample failed at 1e-13 and 1e-15.
      double epsilon = kRegularization;
      Vec theta_dense(Eigen::Index(dense.size()));
      for (size_t k = 0; k < dense.size(); ++k) theta_dense[Eigen::Index(k)] = theta[dense[k]];
      for (;; epsilon *= 100) {
        ++factorizations;
        const auto t = std::chrono::steady_clock::now();
        const bool factored = factor.factorize(normal.form(theta, epsilon), A_dense, theta_dense);
        factor_seconds += seconds_since(t);
        if (trace) fmt::print(stderr, "    form and factor {:.3f}s\n", seconds_since(t));
        if (factored) break;
        if (epsilon > 1e-5) {
          result.message =
              fmt::format("the normal equations could not be factored at iteration {}", it);
          return Outcome::Done;
        }
      }
      // A factor that needed more than the usual regularization is nearly singular already.
      if (watch_pivots && it == 0 && epsilon > kRegularization) return Outcome::DependentRows;
      // Conjugate gradients on the unregularized matrix, preconditioned by the regularized factor:
      // near the optimum a few directions are nearly singular, the factor is poor only there, and
      // CG resolves a few outlying directions in a few steps (plain refinement stalls on them).
      auto solve_normal = [&](const Vec& r, double relative_target) {
        return conjugate_gradients(
            factor, [&](const Vec& v) { return normal_times(A, theta, v); }, r, relative_target,
            cg_steps);
      };
      // Solves the Newton system for the complementarity targets rl (lower) and ru (upper), to
      // `accuracy` relative to its right-hand side.
      auto direction = [&](const Vec& rl, const Vec& ru, double accuracy, Vec& dx, Vec& dy,
                           Vec& dzl, Vec& dzu) {
        Vec r_hat(n);
        for (int j = 0; j < n; ++j)
          r_hat[j] = rd[j] - rl[j] / xl[j] + (has_up[j] ? ru[j] / xu[j] : 0.0);
        dy = solve_normal(rp + times(A, theta.cwiseProduct(r_hat)), accuracy);
        dx = theta.cwiseProduct(transpose_times(A, dy) - r_hat);
        dzl = (rl - zl.cwiseProduct(dx)).cwiseQuotient(xl);
        dzu = Vec::Zero(n);
        for (int j = 0; j < n; ++j)
          if (has_up[j]) dzu[j] = (ru[j] + zu[j] * dx[j]) / xu[j];
      };
      auto steps = [&](const Vec& dx, const Vec& dzl, const Vec& dzu, double& ap, double& ad) {
        Vec dxu = -dx.cwiseProduct(has_up);
        ap = std::min(max_step(xl, dx), max_step(xu, dxu));
        ad = std::min(max_step(zl, dzl),
                      max_step(zu.cwiseProduct(has_up) + (Vec::Ones(n) - has_up), dzu));
      };
      const auto solves_start = std::chrono::steady_clock::now();
      // Predictor: the affine scaling direction.
      Vec dx, dy, dzl, dzu;
      Vec rl = -xl.cwiseProduct(zl), ru = -xu.cwiseProduct(zu).cwiseProduct(has_up);
      direction(rl, ru, kPredictorAccuracy, dx, dy, dzl, dzu);
      double ap, ad;
      steps(dx, dzl, dzu, ap, ad);
      Vec xl_a = xl + ap * dx, xu_a = xu - ap * dx, zl_a = zl + ad * dzl, zu_a = zu + ad * dzu;
      double mu_aff = (xl_a.dot(zl_a) + xu_a.cwiseProduct(has_up).dot(zu_a)) / bounds;
      double sigma = mu > 0 && std::isfinite(mu_aff / mu) ? std::pow(mu_aff / mu, 3) : 0.0;
      // Keep centring while feasibility lags behind complementarity: an iterate that reaches
      // μ ≈ 0 before A·x = b holds is pinned to the bounds and can only take tiny steps.
      const double primal_lag = rp.lpNorm<Eigen::Infinity>() / primal_scale;
      if (primal_lag > 100 * options.tolerance && mu / (1 + std::abs(primal_obj)) < primal_lag)
        sigma = std::max(sigma, 0.1);
      // Corrector: centring plus the second-order term of the predictor.
      Vec rl_c = Vec::Constant(n, sigma * mu) - xl.cwiseProduct(zl) - dx.cwiseProduct(dzl);
      Vec ru_c = (Vec::Constant(n, sigma * mu) - xu.cwiseProduct(zu) + dx.cwiseProduct(dzu))
                     .cwiseProduct(has_up);
      direction(rl_c, ru_c, kCorrectorAccuracy, dx, dy, dzl, dzu);
      steps(dx, dzl, dzu, ap, ad);
      solve_seconds += seconds_since(solves_start);
      ap = std::min(1.0, 0.995 * ap);
      ad = std::min(1.0, 0.995 * ad);
      // With a quadratic term the dual residual moves with x: one step for both keeps the Newton
      // step's reduction of it.
      if (quadratic) ap = ad = std::min(ap, ad);
      if (trace) {
        Vec check = rp - times(A, dx);
        fmt::print(stderr, "    ap {:.3e} ad {:.3e} sigma {:.3e} |rp - A dx| {:.3e} eps {:.0e}\n",
                   ap, ad, sigma, check.lpNorm<Eigen::Infinity>(), epsilon);
      }
      x += ap * dx;
      xl += ap * dx;
      xu -= ap * dx.cwiseProduct(has_up);
      y += ad * dy;
      zl += ad * dzl;
      zu += ad * dzu.cwiseProduct(has_up);
    }
    // A run that stopped short of the tolerance keeps its best point when that is within
    // options.acceptable. Measured on the corpus's shopping centre: lost accuracy at iteration 70
    // with the best point at 1.6e-7.
    if (!result.converged && best_worst <= options.acceptable) {
      x = best.x, y = best.y, zl = best.zl, zu = best.zu;
      result.converged = true;
      // Without a message the loop ran out of iterations.
      const std::string why =
          result.message.empty() ? fmt::format("the limit of {} iterations", options.max_iterations)
                                 : result.message;
      result.message =
          fmt::format("converged to {:.1e} (not {:.0e}: {})", best_worst, options.tolerance, why);
    }
    if (trace)
      fmt::print(stderr,
                 "{} factorizations ({:.3f} s with forming), {} conjugate gradient steps; "
                 "directions {:.3f} s\n",
                 factorizations, factor_seconds, cg_steps, solve_seconds);
    // The dropped rows must hold too: if one was not truly dependent, the answer is not trusted.
    if (result.converged) {
      const double scale =
          std::max(b_norm, 1 + (A_used.cwiseAbs() * x.cwiseAbs()).lpNorm<Eigen::Infinity>());
      Vec b_used(A_used.rows());
      for (int r = 0, u = 0; r < p.rows; ++r)
        if (used[r]) b_used[u++] = p.b[r];
      const double residual = (b_used - A_used * x).lpNorm<Eigen::Infinity>() / scale;
      if (residual > 100 * options.tolerance) {
        result.converged = false;
        result.message =
            m < m_used ? "a row taken as dependent does not hold at the solution"
                       : fmt::format("its best point meets the equations only to {:.1e}", residual);
      }
    }
    result.objective = c.dot(x) + 0.5 * x.dot(q.cwiseProduct(x));
    result.x.assign(x.data(), x.data() + n);
    result.y.assign(p.rows, 0.0);
    for (int r = 0; r < p.rows; ++r)
      if (row_map[r] >= 0) result.y[r] = y[row_map[r]];
    result.z_lower.assign(zl.data(), zl.data() + n);
    result.z_upper.assign(zu.data(), zu.data() + n);
    if (!result.converged && result.message.empty())
      result.message = fmt::format("the interior point method did not converge in {} iterations",
                                   result.iterations);
    return Outcome::Done;
  };
  if (attempt(std::vector<char>(size_t(m_used), 0), true) == Outcome::DependentRows) {
    if (trace) fmt::print(stderr, "dependent rows: solving again without them\n");
    result = IpmResult{};
    attempt(dependent_rows(without_dense(A_used)), false);
  }
  return result;
}

}  // namespace lego::physics
