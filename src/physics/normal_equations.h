#pragma once
// The linear algebra under the interior point method: an order for the normal matrix A·Θ·Aᵀ,
// the matrix formed in it on a pattern fixed once, CHOLMOD's factor of it with the dense columns
// as rank-one updates, and the rows of A that depend on others. Internal to
// physics (it exposes Eigen types); interior_point.h is the interface.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace lego::physics {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major, sorted rows in each column

// A column-major matrix (column j's entries start[j] to start[j + 1] − 1 of index and value) on
// the rows that row_map sends somewhere (−1: left out), renumbered by it: each column's rows
// sorted, zeros dropped, a row repeated within a column summed.
SparseMatrix renumber_rows(int rows, int columns, const int* start, const int* index,
                           const double* value, const std::vector<int>& row_map);

// An order of A's rows for factoring A·Θ·Aᵀ, postordered: of minimum degree (AMD) and METIS's
// nested dissection, on the rows and, when `body` gives each row's body, on the bodies (each
// body's rows then taken together), the one whose factor takes the fewest flops. METIS on the
// rows, the costliest by far, only where the factor would be broad and the model is not a chain of
// layers. Row rows[k] of A is row k of the matrix factored.
struct RowOrder {
  std::vector<int> rows;  // empty: no order (CHOLMOD ran out of memory), never the best
  std::string method;     // "AMD on the rows", "METIS on the bodies", ...
  double flops = std::numeric_limits<double>::infinity(), entries = 0;  // of its factor
};
RowOrder fill_reducing_order(const SparseMatrix& A, const std::vector<int>& body = {});

// The lower triangle of A·Θ·Aᵀ, rows and columns in a fill-reducing order, on a pattern fixed
// once: each column's outer product lands on known positions, so forming it per iteration is a
// scatter of Σ nnz(a_j)² / 2 products (8x faster than a general sparse product at 8,558
// bricks). Formed in its order, CHOLMOD reads it as it is; in any other it transposed the
// matrix twice per factorization (a tenth of the factorization's time on tower-2000).
class NormalMatrix {
 public:
  NormalMatrix(const SparseMatrix& A, const std::vector<int>& order);

  // The lower triangle of P·(A·diag(theta)·Aᵀ + shift·diag(A·diag(theta)·Aᵀ))·Pᵀ.
  const SparseMatrix& form(const Eigen::VectorXd& theta, double shift);

 private:
  SparseMatrix A_;  // A's rows permuted
  SparseMatrix matrix_;
  std::vector<int> slots_, diagonal_;
};

// The factor of a normal matrix M + D·Θ_D·Dᵀ whose few dense columns D are kept out of M (they
// would fill it in). M, as NormalMatrix forms it in a fill-reducing order, is factored by
// CHOLMOD's supernodal LLᵀ, analysed once; each dense column is a rank-one update of that factor
// in product form. Vectors, D and the pivots are in A's row order: the permutation stays inside
// (the sparse products with A run faster in A's own order, where a column's rows are close). Near
// the optimum M is nearly singular and Θ_D huge, and there the Sherman-Morrison-Woodbury formula,
// which subtracts two large nearly equal vectors, lost every digit (the crate sample's
// preconditioner left all of the right-hand side as residual, where M's own factor left 1e-9 of
// it); the product form is stable (Goldfarb and Scheinberg, "A product-form Cholesky factorization
// method for handling dense columns in interior point methods for linear programming", 2004).
class NormalFactor {
 public:
  explicit NormalFactor(std::vector<int> order);
  ~NormalFactor();
  NormalFactor(const NormalFactor&) = delete;
  NormalFactor& operator=(const NormalFactor&) = delete;

  void analyse(const SparseMatrix& lower);
  // False when M is not positive definite.
  bool factorize(const SparseMatrix& lower, const Eigen::MatrixXd& dense,
                 const Eigen::VectorXd& dense_theta);
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const;
  // The pivots L_kk², by row of the matrix: one near zero marks a row that (numerically) depends
  // on the rows eliminated before it.
  Eigen::VectorXd pivots() const;

 private:
  // D + α·z·zᵀ = L̃·D̃·L̃ᵀ (D diagonal): L̃ is the identity plus the strictly lower part of z·βᵀ.
  struct RankOne {
    Eigen::VectorXd z, beta;
    Eigen::VectorXd solve_lower(Eigen::VectorXd b) const;  // L̃⁻¹·b
    Eigen::VectorXd solve_upper(Eigen::VectorXd c) const;  // L̃⁻ᵀ·c
  };
  Eigen::VectorXd to_factor_order(const Eigen::VectorXd& v) const;    // P·v
  Eigen::VectorXd from_factor_order(const Eigen::VectorXd& v) const;  // Pᵀ·v

  struct Cholmod;
  std::unique_ptr<Cholmod> cholmod_;
  std::vector<int> order_;
  std::vector<RankOne> updates_;
  Eigen::VectorXd diagonal_;  // D̃ after the last update
};

// Solves M·v = r by conjugate gradients on M (`times` applies it), preconditioned by `factor`,
// the factor of M or of M shifted: near an optimum M is nearly singular, the factor is poor only
// in a few directions, and CG resolves them in a few steps (plain refinement stalls on them).
// Stops at relative_target·|r| or after 50 steps; `steps` counts them.
Eigen::VectorXd conjugate_gradients(
    const NormalFactor& factor, const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& times,
    const Eigen::VectorXd& r, double relative_target, long& steps);

// Rows of A that are (numerically) combinations of others, marked 1.
std::vector<char> dependent_rows(const SparseMatrix& A);

}  // namespace lego::physics
