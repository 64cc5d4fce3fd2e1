#include "physics/interior_point.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <mutex>

namespace lego::physics {
namespace {

using Vec = Eigen::VectorXd;
using SpMat = Eigen::SparseMatrix<double>;

// The normal matrix's shift, relative to its diagonal (see where it is factored).
constexpr double kRegularization = 1e-14;

// How far the conjugate gradients solve each Newton direction, relative to its right-hand side.
// The step taken is the corrector's: to 1e-10, measured against 1e-13 (needed while the shift
// was 1e-12), the same iterations everywhere and a third fewer CG steps (tower-2000 99 -> 62,
// box-2000 52 -> 32, the crate sample 20 -> 10). The predictor only sets σ and the corrector's
// second-order term: to 1e-6 it costs half the CG steps (tower-2000 62 -> 34) with the same
// iterations on the towers, boxes and samples up to 2,000 bricks (box-8000 one more, 25);
// tower-2000 and box-2000 x0.89.
constexpr double kCorrectorAccuracy = 1e-10, kPredictorAccuracy = 1e-6;

double max_step(const Vec& v, const Vec& dv) {
  double alpha = 1.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (dv[i] < 0) alpha = std::min(alpha, -v[i] / dv[i]);
  return alpha;
}

// Rows of A that are (numerically) combinations of others: with rows scaled to unit length, a
// Cholesky factorization of A·Aᵀ + δI has a pivot near δ exactly where a row adds nothing to the
// rows eliminated before it. Such dependencies are structural here (a sub-assembly that hangs on
// one stacked contact may spin about its vertical axis: the twist rows repeat), so the pivots are
// at roundoff level, far below those of independent rows.
//
// CHOLMOD's supernodal factorization with METIS, read back as a simplicial factor for its
// diagonal: 0.2 s where Eigen's simplicial LDLᵀ took 2.5 s on a 3,300-brick model. Should
// roundoff make the shifted matrix indefinite, the LDLᵀ decides instead.
std::vector<char> dependent_rows_ldlt(const SpMat& S) {
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  ldlt.setShift(1e-14);
  ldlt.compute(S);
  std::vector<char> dependent(S.rows(), 0);
  if (ldlt.info() != Eigen::Success) return dependent;
  const Vec pivots = ldlt.vectorD();  // a copy: vectorD() returns by value
  const auto& original = ldlt.permutationPinv().indices();
  for (Eigen::Index k = 0; k < S.rows(); ++k)
    if (pivots[k] < 1e-10) dependent[original[k]] = 1;
  return dependent;
}

std::vector<char> dependent_rows(const SpMat& A) {
  Vec scale = Vec::Ones(A.rows());
  SpMat AAt = A * A.transpose();
  for (Eigen::Index r = 0; r < A.rows(); ++r)
    scale[r] = 1 / std::sqrt(std::max(AAt.coeff(r, r), 1e-300));
  SpMat S = scale.asDiagonal() * AAt * scale.asDiagonal();
  std::vector<char> dependent(A.rows(), 0);
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_METIS;
  common.supernodal = CHOLMOD_SUPERNODAL;
  SpMat lower = S.triangularView<Eigen::Lower>();
  cholmod_sparse view = Eigen::viewAsCholmod(lower);
  view.stype = -1;
  auto t0 = std::chrono::steady_clock::now();
  cholmod_factor* factor = cholmod_analyze(&view, &common);
  auto t1 = std::chrono::steady_clock::now();
  double shift[2] = {1e-12, 0};
  bool ok = factor && cholmod_factorize_p(&view, shift, nullptr, 0, factor, &common) &&
            common.status == CHOLMOD_OK &&
            cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, factor, &common);
  if (std::getenv("LEGO_IPM_TRACE"))
    fmt::print(stderr, "dependent rows: analyse {:.3f}s factor {:.3f}s\n",
               std::chrono::duration<double>(t1 - t0).count(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
  if (ok) {
    const auto* column = static_cast<const int*>(factor->p);
    const auto* values = static_cast<const double*>(factor->x);
    const auto* perm = static_cast<const int*>(factor->Perm);
    for (size_t k = 0; k < factor->n; ++k) {
      const double l = values[column[k]];  // a simplicial column starts with its diagonal
      if (l * l < 1e-10) dependent[perm[k]] = 1;
    }
  }
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  return ok ? dependent : dependent_rows_ldlt(S);
}

// CHOLMOD's supernodal LLᵀ, with the pivots (L_kk², by original row) readable.
class PivotedLLT : public Eigen::CholmodSupernodalLLT<SpMat> {
 public:
  Vec pivots() const {
    const cholmod_factor* f = m_cholmodFactor;
    Vec by_row(Eigen::Index(f->n));
    const auto* perm = static_cast<const int*>(f->Perm);
    const auto* x = static_cast<const double*>(f->x);
    const auto* super = static_cast<const int*>(f->super);
    const auto* pi = static_cast<const int*>(f->pi);
    const auto* px = static_cast<const int*>(f->px);
    for (size_t k = 0; k < f->nsuper; ++k) {
      const int columns = super[k + 1] - super[k], rows = pi[k + 1] - pi[k];
      for (int c = 0; c < columns; ++c) {
        const double l = x[px[k] + c * (rows + 1)];  // dense column-major block, diagonal
        by_row[perm[super[k] + c]] = l * l;
      }
    }
    return by_row;
  }
};

// The lower triangle of A·Θ·Aᵀ on a pattern fixed once: each column's outer product lands on
// known positions, so forming it per iteration is a scatter of Σ nnz(a_j)² / 2 products (8x
// faster than a general sparse product at 8,558 bricks).
class NormalMatrix {
 public:
  explicit NormalMatrix(const SpMat& A) : A_(A) {
    const Eigen::Index m = A.rows();
    std::vector<Eigen::Triplet<double>> entries;
    for (Eigen::Index r = 0; r < m; ++r) entries.emplace_back(r, r, 0.0);
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      for (SpMat::InnerIterator p(A, j); p; ++p)
        for (SpMat::InnerIterator q(A, j); q && q.row() <= p.row(); ++q)
          entries.emplace_back(p.row(), q.row(), 0.0);
    matrix_.resize(m, m);
    matrix_.setFromTriplets(entries.begin(), entries.end());  // sums duplicates: the pattern
    matrix_.makeCompressed();
    auto position = [&](Eigen::Index row, Eigen::Index col) {
      const int* begin = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col];
      const int* end = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col + 1];
      return int(std::lower_bound(begin, end, int(row)) - matrix_.innerIndexPtr());
    };
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      for (SpMat::InnerIterator p(A, j); p; ++p)
        for (SpMat::InnerIterator q(A, j); q && q.row() <= p.row(); ++q)
          slots_.push_back(position(p.row(), q.row()));
    diagonal_.resize(size_t(m));
    for (Eigen::Index r = 0; r < m; ++r) diagonal_[size_t(r)] = position(r, r);
  }

  // The lower triangle of A·diag(theta)·Aᵀ + shift·diag(A·diag(theta)·Aᵀ).
  const SpMat& form(const Vec& theta, double shift) {
    double* value = matrix_.valuePtr();
    std::fill(value, value + matrix_.nonZeros(), 0.0);
    size_t k = 0;
    for (Eigen::Index j = 0; j < A_.cols(); ++j) {
      const double t = theta[j];
      for (SpMat::InnerIterator p(A_, j); p; ++p) {
        const double tp = t * p.value();
        for (SpMat::InnerIterator q(A_, j); q && q.row() <= p.row(); ++q)
          value[slots_[k++]] += tp * q.value();
      }
    }
    for (int d : diagonal_) value[d] *= 1 + shift;
    return matrix_;
  }

 private:
  const SpMat& A_;
  SpMat matrix_;
  std::vector<int> slots_, diagonal_;
};

// Debian's CHOLMOD opens an OpenMP team of four (its compiled-in CHOLMOD_OMP_NUM_THREADS) for
// small loops in every supernode, whatever OMP_NUM_THREADS says. On two cores those teams cost
// more than their loops: 600,000 futex calls and as much system time as user time in one
// 2,000-brick solve, 1.5 s against 1.05 s with them serial. The BLAS keeps its own threads for
// the large supernodes. OpenMP parallel regions nested zero levels deep run on one thread.
void serialize_openmp_regions() {
  static std::once_flag once;
  std::call_once(once, [] {
    using Set = void (*)(int);
    if (auto set = reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) set(0);
  });
}

}  // namespace

IpmResult solve_interior_point(const IpmProblem& p, const IpmOptions& options) {
  serialize_openmp_regions();
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
  std::vector<Eigen::Triplet<double>> used_triplets;
  for (int j = 0; j < n; ++j)
    for (int k = p.start[j]; k < p.start[j + 1]; ++k)
      if (p.value[k] != 0 && used_row_map[p.index[k]] >= 0)
        used_triplets.emplace_back(used_row_map[p.index[k]], j, p.value[k]);
  SpMat A_used(m, n);
  A_used.setFromTriplets(used_triplets.begin(), used_triplets.end());
  // Dense columns (the scale w of the stability LP touches every loaded row) stay out of the
  // factored matrix: A·Θ·Aᵀ would be dense. The factor of the rest preconditions the whole
  // through the Sherman-Morrison-Woodbury formula, and the conjugate gradients below run on the
  // true matrix, so the answer is the same.
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
  // single contact), so the first attempt keeps every row and reads the first factor's pivots:
  // a pivot at the regularization's level marks a dependent row, and only then are such rows
  // found properly and dropped (the solution is checked against them at the end).
  enum class Outcome { Done, DependentRows };
  auto attempt = [&](const std::vector<char>& dependent, bool watch_pivots) -> Outcome {
    std::vector<int> row_map = used_row_map;
    std::vector<Eigen::Triplet<double>> triplets = used_triplets;
    int m = m_used;
    std::vector<int> kept_row(m, -1);
    int kept = 0;
    for (int r = 0; r < m; ++r)
      if (!dependent[r]) kept_row[r] = kept++;
    triplets.erase(std::remove_if(triplets.begin(), triplets.end(),
                                  [&](const auto& t) { return dependent[t.row()]; }),
                   triplets.end());
    for (auto& t : triplets) t = Eigen::Triplet<double>(kept_row[t.row()], t.col(), t.value());
    for (int r = 0; r < p.rows; ++r)
      if (row_map[r] >= 0) row_map[r] = kept_row[row_map[r]];
    m = kept;
    if (trace)
      fmt::print(stderr, "rows {}, {} with variables, {} kept\n", p.rows, A_used.rows(), kept);
    SpMat A(m, n);
    A.setFromTriplets(triplets.begin(), triplets.end());
    SpMat At = A.transpose();
    const SpMat A_abs = A.cwiseAbs();
    const SpMat A_sparse = without_dense(A);
    NormalMatrix normal(A_sparse);
    Eigen::MatrixXd A_dense(m, Eigen::Index(dense.size()));
    for (size_t k = 0; k < dense.size(); ++k) A_dense.col(Eigen::Index(k)) = A.col(dense[k]);
    Vec b(m), c = Eigen::Map<const Vec>(p.c.data(), n);
    for (int r = 0; r < p.rows; ++r)
      if (row_map[r] >= 0) b[row_map[r]] = p.b[r];

    const Vec lo = Eigen::Map<const Vec>(p.lower.data(), n),
              up = Eigen::Map<const Vec>(p.upper.data(), n);
    Vec has_up(n);
    for (int j = 0; j < n; ++j) has_up[j] = std::isfinite(up[j]) ? 1.0 : 0.0;
    // Start inside the bounds, near zero: the middle of a narrow box, else zero moved at least a
    // unit inside the bounds (a wide box's middle can be absurdly far from any solution).
    Vec x(n), y = Vec::Zero(m);
    for (int j = 0; j < n; ++j)
      x[j] = has_up[j] && up[j] - lo[j] <= 2
                 ? 0.5 * (lo[j] + up[j])
                 : std::clamp(0.0, lo[j] + 1, has_up[j] ? up[j] - 1 : 1e300);
    // The distances to the bounds are carried as variables of their own, moved by the same steps
    // as x: recomputed as u − x they would cancel to exactly zero for x → u.
    Vec xl = x - lo, xu = Vec::Ones(n);
    for (int j = 0; j < n; ++j)
      if (has_up[j]) xu[j] = up[j] - x[j];
    // Multipliers start at 1/slack, so every complementarity product starts at 1: a centred start.
    // (At 1 they made the products of the wide support boxes 10³ and cost a dozen iterations.)
    Vec zl = xl.cwiseInverse(), zu = xu.cwiseInverse().cwiseProduct(has_up);

    // CHOLMOD's supernodal factorization: measured faster than Eigen's simplicial one at every size
    // from 500 bricks up (0.67 s against 0.92 s for a whole solve at 516 bricks, 1.5 s against 3.0
    // s at 1,000); the same at 200.
    PivotedLLT llt;
    llt.cholmod().print = 0;  // failures are handled here, not printed
    // Nested dissection (METIS) rather than CHOLMOD's default AMD: on hollow boxes it cuts the
    // factor's flops from 59M to 35M at 516 bricks and the whole solve by about a quarter at 500
    // to 2,000 bricks.
    llt.cholmod().nmethods = 1;
    llt.cholmod().method[0].ordering = CHOLMOD_METIS;
    llt.cholmod().postorder = 1;
    bool analysed = false;
    const double b_norm = 1 + b.lpNorm<Eigen::Infinity>(), c_norm = 1 + c.lpNorm<Eigen::Infinity>();
    const int bounds = n + int(has_up.sum());

    long cg_steps = 0, factorizations = 0;
    double factor_seconds = 0, solve_seconds = 0;  // for the trace
    auto since = [](std::chrono::steady_clock::time_point t) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    for (int it = 0; it < options.max_iterations; ++it) {
      result.iterations = it;
      Vec rp = b - A * x;
      Vec rd = c - At * y - zl + zu.cwiseProduct(has_up);
      double gap_sum = xl.dot(zl) + xu.cwiseProduct(has_up).dot(zu);
      double mu = gap_sum / bounds;
      double primal_obj = c.dot(x);
      double dual_obj = b.dot(y) + lo.dot(zl);
      for (int j = 0; j < n; ++j)
        if (has_up[j]) dual_obj -= up[j] * zu[j];
      if (!std::isfinite(mu) || !std::isfinite(rp.squaredNorm())) {
        result.message = fmt::format("the interior point method broke down at iteration {}", it);
        break;
      }
      // Residuals relative to the size of what they balance: here b is often zero, while the
      // terms of A·x are not.
      const double primal_scale =
          std::max(b_norm, 1 + (A_abs * x.cwiseAbs()).lpNorm<Eigen::Infinity>());
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
      // Θ = (zl/xl + zu/xu)⁻¹ and the normal matrix A·Θ·Aᵀ + δI.
      if (trace)
        fmt::print(stderr, "it {:3} mu {:.3e} rp {:.3e} rd {:.3e} pobj {:.9e} dobj {:.9e}\n", it,
                   mu, rp.lpNorm<Eigen::Infinity>(), rd.lpNorm<Eigen::Infinity>(), primal_obj,
                   dual_obj);
      Vec theta(n);
      for (int j = 0; j < n; ++j)
        theta[j] = 1.0 / (zl[j] / xl[j] + (has_up[j] ? zu[j] / xu[j] : 0.0));
      auto t0 = std::chrono::steady_clock::now();
      if (!analysed) {
        llt.analyzePattern(normal.form(theta, 0.0));
        analysed = true;
      }
      auto t1 = std::chrono::steady_clock::now();
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
      for (;; epsilon *= 100) {
        llt.factorize(normal.form(theta, epsilon));
        ++factorizations;
        if (llt.info() == Eigen::Success) break;
        if (epsilon > 1e-5) {
          result.message =
              fmt::format("the normal equations could not be factored at iteration {}", it);
          return Outcome::Done;
        }
      }
      if (watch_pivots && it == 0) {
        // A factor that needed more than the usual regularization is nearly singular already.
        if (epsilon > kRegularization) return Outcome::DependentRows;
        const Vec pivots = llt.pivots();
        const SpMat& M = normal.form(theta, 0.0);
        for (Eigen::Index r = 0; r < m; ++r)
          if (pivots[r] < 1e-10 * M.coeff(r, r)) return Outcome::DependentRows;
      }
      auto t2 = std::chrono::steady_clock::now();
      factor_seconds += since(t0);
      if (trace)
        fmt::print(stderr, "    analyse {:.3f}s form and factor {:.3f}s\n",
                   std::chrono::duration<double>(t1 - t0).count(),
                   std::chrono::duration<double>(t2 - t1).count());
      const auto solves_start = std::chrono::steady_clock::now();
      // The dense columns' part, for the Woodbury formula: (P + D·Θ_D·Dᵀ)⁻¹ r =
      // P⁻¹r − U·(Θ_D⁻¹ + Dᵀ·U)⁻¹·Dᵀ·P⁻¹r with U = P⁻¹·D.
      Eigen::MatrixXd U(m, Eigen::Index(dense.size()));
      Eigen::LDLT<Eigen::MatrixXd> small;
      if (!dense.empty()) {
        for (size_t k = 0; k < dense.size(); ++k)
          U.col(Eigen::Index(k)) = llt.solve(Vec(A_dense.col(Eigen::Index(k))));
        Eigen::MatrixXd S = A_dense.transpose() * U;
        for (size_t k = 0; k < dense.size(); ++k)
          S(Eigen::Index(k), Eigen::Index(k)) += 1 / theta[dense[k]];
        small.compute(S);
      }
      auto precondition = [&](const Vec& r) {
        Vec v = llt.solve(r);
        if (!dense.empty()) v -= U * small.solve(A_dense.transpose() * v);
        return v;
      };
      // Conjugate gradients on the unregularized matrix, preconditioned by the regularized factor:
      // near the optimum a few directions are nearly singular, the factor is poor only there, and
      // CG resolves a few outlying directions in a few steps (plain refinement stalls on them).
      auto solve_normal = [&](const Vec& r, double relative_target) {
        auto apply = [&](const Vec& v) { return Vec(A * theta.cwiseProduct(At * v)); };
        Vec v = precondition(r);
        Vec residual = r - apply(v);
        const double target = relative_target * r.norm();
        if (residual.norm() <= target) return v;
        Vec z = precondition(residual), d = z;
        double rz = residual.dot(z);
        for (int k = 0; k < 50 && residual.norm() > target; ++k) {
          ++cg_steps;
          Vec Md = apply(d);
          const double curvature = d.dot(Md);
          if (!(curvature > 0)) break;
          const double alpha = rz / curvature;
          v += alpha * d;
          residual -= alpha * Md;
          z = precondition(residual);
          const double rz_next = residual.dot(z);
          d = z + (rz_next / rz) * d;
          rz = rz_next;
        }
        return v;
      };
      // Solves the Newton system for the complementarity targets rl (lower) and ru (upper), to
      // `accuracy` relative to its right-hand side.
      auto direction = [&](const Vec& rl, const Vec& ru, double accuracy, Vec& dx, Vec& dy,
                           Vec& dzl, Vec& dzu) {
        Vec r_hat(n);
        for (int j = 0; j < n; ++j)
          r_hat[j] = rd[j] - rl[j] / xl[j] + (has_up[j] ? ru[j] / xu[j] : 0.0);
        dy = solve_normal(rp + A * theta.cwiseProduct(r_hat), accuracy);
        dx = theta.cwiseProduct(At * dy - r_hat);
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
      solve_seconds += since(solves_start);
      ap = std::min(1.0, 0.995 * ap);
      ad = std::min(1.0, 0.995 * ad);
      if (trace) {
        Vec check = rp - A * dx;
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
      if ((b_used - A_used * x).lpNorm<Eigen::Infinity>() / scale > 100 * options.tolerance) {
        result.converged = false;
        result.message = "a row taken as dependent does not hold at the solution";
      }
    }
    result.objective = c.dot(x);
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

int set_blas_threads(int threads) {
  using Get = int (*)();
  using Set = void (*)(int);
  auto get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  auto set = reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!get || !set) return 0;
  const int previous = get();
  set(threads);
  return previous;
}

}  // namespace lego::physics
