#include "physics/normal_equations.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>

namespace lego::physics {
namespace {

using Vec = Eigen::VectorXd;
using SpMat = SparseMatrix;

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

}  // namespace

std::vector<char> dependent_rows(const SpMat& A) {
  serialize_openmp_regions();
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

NormalMatrix::NormalMatrix(const SpMat& A) : A_(A) {
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

const SpMat& NormalMatrix::form(const Vec& theta, double shift) {
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

struct NormalFactor::Cholmod {
  PivotedLLT llt;
};

NormalFactor::NormalFactor() : cholmod_(std::make_unique<Cholmod>()) {
  serialize_openmp_regions();
  auto& common = cholmod_->llt.cholmod();
  common.print = 0;  // failures are handled by the caller, not printed
  // Nested dissection (METIS) rather than CHOLMOD's default AMD: on hollow boxes it cuts the
  // factor's flops from 59M to 35M at 516 bricks and the whole solve by about a quarter at 500
  // to 2,000 bricks.
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_METIS;
  common.postorder = 1;
}

NormalFactor::~NormalFactor() = default;

void NormalFactor::analyse(const SpMat& lower) {
  cholmod_->llt.analyzePattern(lower);
}

bool NormalFactor::factorize(const SpMat& lower) {
  cholmod_->llt.factorize(lower);
  return cholmod_->llt.info() == Eigen::Success;
}

Vec NormalFactor::solve(const Vec& r) const {
  return cholmod_->llt.solve(r);
}

Vec NormalFactor::pivots() const {
  return cholmod_->llt.pivots();
}

}  // namespace lego::physics
