#include "physics/normal_equations.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <numeric>

#include "core/stopwatch.h"

namespace lego::physics {
namespace {

using Vec = Eigen::VectorXd;
using SpMat = SparseMatrix;

// Below this many flops per entry of L, METIS is not tried on the rows (fill_reducing_order).
// Measured with AMD on the rows, flops per entry and METIS's flops against AMD's: towers of 552
// and 2,244 bricks 77 and 85 (METIS x0.95 and x1.01); the crate sample 105 (x0.81); the globe
// sample 218 (x0.61); hollow boxes of 516 to 8,558 bricks 163 to 586 (x0.38 to x0.27); bunnies,
// the teapot and the paper's table 328 to 689 (x0.60 to x0.45).
constexpr double kNarrowFactor = 100;
// Where METIS on the bodies needs this many times AMD's flops on them, the model is a chain of
// layers (a tower), and METIS on the rows is not tried either. The orders' flops, measured on
// 2026-12-02 (AMD, METIS on the bodies; AMD, METIS on the rows):
// - solid 16 x 16 towers, 2,229 bricks: 5.8e8, 9.7e8; 1.05e9, 7.9e8
// - 8,940 bricks: 3.1e9, 5.1e9; 4.7e9, 4.2e9
// - a 10 x 10 tower of 2,000 bricks: 3.1e7, 8.5e7; 6.3e7, 6.4e7
// - a solid block of 20,778 bricks: 3.3e11, 1.6e11; 4.9e11, 1.3e11
// - hollow boxes, 2,116 bricks: 2.9e8, 3.0e8; 4.9e8, 1.6e8
// - 21,270 bricks: 1.9e10, 1.3e10; 2.4e10, 6.9e9
// - the bunny 30 bricks high: 3.5e8, 4.0e8; 4.5e8, 2.7e8
// METIS on the bodies against AMD on them: the towers x1.6 to x2.7, the bench's cantilever x1.7;
// the globe and the spider x1.3, the crate x1.2, the bunny x1.1, the boxes x0.65 to x1.0, the
// block x0.5. METIS on the rows takes 5 to 10 times AMD's time on them (1.6 s on the block, whose
// factorizations it makes 21% cheaper; 0.55 s on the 8,940-brick tower, where it lost). On the
// corpus's 318 analyses the factors' flops are 1% fewer in all than with the rows' orders alone.
constexpr double kChainLike = 1.5;

// A factorization runs on the thread that asks for it, nowhere else.
//
// Debian's CHOLMOD opens an OpenMP team of four (its compiled-in CHOLMOD_OMP_NUM_THREADS) for
// small loops in every supernode, whatever OMP_NUM_THREADS says. On two cores those teams cost
// more than their loops: 600,000 futex calls and as much system time as user time in one
// 2,000-brick solve, 1.5 s against 1.05 s with them serial. OpenMP parallel regions nested zero
// levels deep run on one thread. The setting is each thread's own (libgomp keeps it per thread):
// set once on every thread that factors, or brickcheck's second worker opened teams of four.
//
// OpenBLAS (the BLAS under CHOLMOD's large supernodes) starts a thread per core, and its
// threaded kernels round differently from one thread: legolize's build order on the bunny at
// height 40 made 130 steps with two BLAS threads and 131 with one, so the output depended on the
// machine's cores and on --jobs (which ran one BLAS thread per analysis); brickcheck's corpus
// listed equally weak contacts in another order under -j 1 than under -j 2. One BLAS thread, for
// the whole process (OpenBLAS keeps the count process-wide): the bunny's build order 70.1 s
// against 72.2 s with two, with 4 s of system time against 29 s (idle threads spin); at 2,000
// and 8,000 bricks two threads had gained nothing or 7% (docs/stability-lp.md, 2026-11-22).
void keep_factorizations_on_this_thread() {
  using Get = int (*)();
  using Set = void (*)(int);
  static const auto blas_threads =
      reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  static const auto set_blas_threads =
      reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (blas_threads && set_blas_threads && blas_threads() != 1) set_blas_threads(1);
  thread_local bool serialized = false;
  if (serialized) return;
  serialized = true;
  if (auto set = reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) set(0);
}

// METIS (5.1, as Debian builds it) keeps its random number generator in process-wide state that
// each call seeds at its start: two orders computed at once (brickcheck -j 2, a town's structures
// two at a time) draw from one stream, and each order then depended on the other's timing. With
// another order the roundoff differs, and on the corpus's rocket sculpture the dependent rows'
// pivots went unseen in one run of ten under -j 2 (no equilibrium, where C_M is 71.5 gf). One
// METIS call at a time: every order is the one a single thread gets.
std::unique_lock<std::mutex> metis_turn(int ordering) {
  static std::mutex mutex;
  return ordering == CHOLMOD_METIS ? std::unique_lock(mutex) : std::unique_lock<std::mutex>();
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

  ~PivotedLLT() {
    cholmod_free_dense(&x_, &cholmod());
    cholmod_free_dense(&y_, &cholmod());
    cholmod_free_dense(&e_, &cholmod());
  }

  // L⁻¹·r (system CHOLMOD_L) or L⁻ᵀ·r (CHOLMOD_Lt), in place. The factor's order is natural
  // (the matrix comes in its fill-reducing order), so no permutation goes with them. CHOLMOD's
  // workspace is kept from one solve to the next rather than allocated and cleared each time.
  void half_solve(int system, Vec& r) {
    cholmod_dense b = Eigen::viewAsCholmod(r);
    cholmod_solve2(system, m_cholmodFactor, &b, nullptr, &x_, nullptr, &y_, &e_, &cholmod());
    r = Eigen::Map<const Vec>(static_cast<const double*>(x_->x), r.size());
  }

 private:
  cholmod_dense *x_ = nullptr, *y_ = nullptr, *e_ = nullptr;
};

// A's entries grouped by row: row r's are entry[start[r]] to entry[start[r + 1] − 1], positions
// in A's arrays, in column order; column[k] is the column of position k.
struct EntriesByRow {
  std::vector<int> start, entry, column;

  explicit EntriesByRow(const SpMat& A)
      : start(size_t(A.rows()) + 1, 0), entry(size_t(A.nonZeros())), column(entry.size()) {
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      for (int k = outer[j]; k < outer[j + 1]; ++k)
        ++start[size_t(inner[k]) + 1], column[size_t(k)] = int(j);
    for (size_t r = 0; r + 1 < start.size(); ++r) start[r + 1] += start[r];
    std::vector<int> next(start.begin(), start.end() - 1);
    for (size_t k = 0; k < entry.size(); ++k) entry[size_t(next[size_t(inner[k])]++)] = int(k);
  }
};

// The pattern of A·Aᵀ's lower triangle (zeros as values): column q holds q and every row p > q
// that shares a column of A with it (those after q's entry: rows are sorted in A's columns). A
// symbolic product, whose work is that of forming the matrix once.
SpMat lower_normal_pattern(const SpMat& A, const EntriesByRow& rows) {
  const int m = int(A.rows());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  std::vector<int> start{0}, pattern, mark(static_cast<size_t>(m), -1);
  for (int q = 0; q < m; ++q) {
    const size_t begin = pattern.size();
    pattern.push_back(q);
    mark[size_t(q)] = q;
    for (int e = rows.start[size_t(q)]; e < rows.start[size_t(q) + 1]; ++e) {
      const int k = rows.entry[size_t(e)], j = rows.column[size_t(k)];
      for (int kk = k + 1; kk < outer[j + 1]; ++kk)
        if (mark[size_t(inner[kk])] != q) mark[size_t(inner[kk])] = q, pattern.push_back(inner[kk]);
    }
    std::sort(pattern.begin() + long(begin), pattern.end());
    start.push_back(int(pattern.size()));
  }
  const std::vector<double> zeros(pattern.size(), 0.0);
  return Eigen::Map<const SpMat>(m, m, Eigen::Index(pattern.size()), start.data(), pattern.data(),
                                 zeros.data());
}

// A with row order[k] moved to row k.
SpMat permute_rows(SpMat A, const std::vector<int>& order) {
  A.makeCompressed();
  std::vector<int> position(order.size());
  for (size_t k = 0; k < order.size(); ++k) position[size_t(order[k])] = int(k);
  return renumber_rows(int(A.rows()), int(A.cols()), A.outerIndexPtr(), A.innerIndexPtr(),
                       A.valuePtr(), position);
}

}  // namespace

SpMat renumber_rows(int rows, int columns, const int* start, const int* index, const double* value,
                    const std::vector<int>& row_map) {
  std::vector<int> outer{0}, inner;
  std::vector<double> values;
  inner.reserve(size_t(start[columns]));
  values.reserve(size_t(start[columns]));
  std::vector<std::pair<int, double>> column;
  for (int j = 0; j < columns; ++j) {
    column.clear();
    for (int k = start[j]; k < start[j + 1]; ++k)
      if (value[k] != 0 && row_map[size_t(index[k])] >= 0)
        column.emplace_back(row_map[size_t(index[k])], value[k]);
    if (!std::is_sorted(column.begin(), column.end())) std::sort(column.begin(), column.end());
    for (size_t e = 0; e < column.size(); ++e) {
      if (e > 0 && column[e].first == column[e - 1].first)
        values.back() += column[e].second;
      else
        inner.push_back(column[e].first), values.push_back(column[e].second);
    }
    outer.push_back(int(inner.size()));
  }
  return Eigen::Map<const SpMat>(rows, columns, Eigen::Index(inner.size()), outer.data(),
                                 inner.data(), values.data());
}

std::vector<char> dependent_rows(const SpMat& A) {
  keep_factorizations_on_this_thread();
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
  cholmod_factor* factor = [&] {
    const auto turn = metis_turn(common.method[0].ordering);
    return cholmod_analyze(&view, &common);
  }();
  auto t1 = std::chrono::steady_clock::now();
  double shift[2] = {1e-12, 0};
  bool ok = factor && cholmod_factorize_p(&view, shift, nullptr, 0, factor, &common) &&
            common.status == CHOLMOD_OK &&
            cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, factor, &common);
  if (std::getenv("LEGO_IPM_TRACE"))
    fmt::print(stderr, "dependent rows: analyse {:.3f}s factor {:.3f}s\n",
               std::chrono::duration<double>(t1 - t0).count(), seconds_since(t1));
  if (ok) {
    const auto* column = static_cast<const int*>(factor->p);
    const auto* values = static_cast<const double*>(factor->x);
    const auto* perm = static_cast<const int*>(factor->Perm);
    double largest_dependent = 0, smallest_other = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < factor->n; ++k) {
      const double l = values[column[k]];  // a simplicial column starts with its diagonal
      if (l * l < 1e-10) {
        dependent[perm[k]] = 1;
        largest_dependent = std::max(largest_dependent, l * l);
      } else {
        smallest_other = std::min(smallest_other, l * l);
      }
    }
    if (std::getenv("LEGO_IPM_TRACE"))
      fmt::print(stderr, "dependent rows: {}, pivots up to {:.1e}; the others' from {:.1e}\n",
                 std::count(dependent.begin(), dependent.end(), 1), largest_dependent,
                 smallest_other);
  }
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  return ok ? dependent : dependent_rows_ldlt(S);
}

NormalMatrix::NormalMatrix(const SpMat& A, const std::vector<int>& order)
    : A_(permute_rows(A, order)) {
  const EntriesByRow rows(A_);
  matrix_ = lower_normal_pattern(A_, rows);
  const int* outer = A_.outerIndexPtr();
  const int* inner = A_.innerIndexPtr();
  // form() visits column j's pairs (a, b), b ≤ a, of its entries in the order a·(a + 1)/2 + b,
  // after those of the columns before it.
  std::vector<size_t> first_pair(size_t(A.cols()) + 1, 0);
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const size_t c = size_t(outer[j + 1] - outer[j]);
    first_pair[size_t(j) + 1] = first_pair[size_t(j)] + c * (c + 1) / 2;
  }
  slots_.resize(first_pair.back());
  diagonal_.resize(size_t(A.rows()));
  std::vector<int> where(size_t(A.rows()));
  for (int q = 0; q < int(A.rows()); ++q) {
    const int begin = matrix_.outerIndexPtr()[q], end = matrix_.outerIndexPtr()[q + 1];
    for (int i = begin; i < end; ++i) where[size_t(matrix_.innerIndexPtr()[i])] = i;
    diagonal_[size_t(q)] = begin;  // q is the first row of its column
    for (int e = rows.start[size_t(q)]; e < rows.start[size_t(q) + 1]; ++e) {
      const int k = rows.entry[size_t(e)], j = rows.column[size_t(k)];
      const size_t b = size_t(k - outer[j]);
      for (size_t a = b; a < size_t(outer[j + 1] - outer[j]); ++a)
        slots_[first_pair[size_t(j)] + a * (a + 1) / 2 + b] =
            where[size_t(inner[size_t(outer[j]) + a])];
    }
  }
}

const SpMat& NormalMatrix::form(const Vec& theta, double shift) {
  double* value = matrix_.valuePtr();
  std::fill(value, value + matrix_.nonZeros(), 0.0);
  // Column j's pairs (a, b), b ≤ a, in the order the constructor laid out their slots; plain
  // pointers rather than iterators that compare rows (3x fewer instructions per pair).
  const int* outer = A_.outerIndexPtr();
  const double* entries = A_.valuePtr();
  const int* slot = slots_.data();
  for (Eigen::Index j = 0; j < A_.cols(); ++j) {
    const double* column = entries + outer[j];
    const int count = outer[j + 1] - outer[j];
    for (int a = 0; a < count; ++a) {
      const double ta = theta[j] * column[a];
      for (int b = 0; b <= a; ++b) value[*slot++] += ta * column[b];
    }
  }
  for (int d : diagonal_) value[d] *= 1 + shift;
  return matrix_;
}

namespace {

// CHOLMOD's symbolic analysis of a lower-triangle pattern: orders and their factors' sizes.
class SymbolicAnalysis {
 public:
  explicit SymbolicAnalysis(SpMat lower) : lower_(std::move(lower)) {
    cholmod_start(&common_);
    common_.print = 0;
    common_.nmethods = 1;
    common_.postorder = 1;                    // so that the supernodes are contiguous
    common_.supernodal = CHOLMOD_SIMPLICIAL;  // the order is wanted, not the supernodes
    view_ = Eigen::viewAsCholmod(lower_);
    view_.stype = -1;
  }
  ~SymbolicAnalysis() { cholmod_finish(&common_); }
  SymbolicAnalysis(const SymbolicAnalysis&) = delete;
  SymbolicAnalysis& operator=(const SymbolicAnalysis&) = delete;

  // CHOLMOD's AMD or METIS order, or (CHOLMOD_GIVEN) `given` postordered. No order when CHOLMOD
  // ran out of memory (it will say so again).
  RowOrder order(int ordering, const std::vector<int>& given = {}) {
    common_.method[0].ordering = ordering;
    const auto turn = metis_turn(ordering);
    cholmod_factor* symbolic = cholmod_analyze_p(
        &view_, given.empty() ? nullptr : const_cast<int*>(given.data()), nullptr, 0, &common_);
    RowOrder out;
    if (!symbolic) return out;
    const auto* perm = static_cast<const int*>(symbolic->Perm);
    out.rows.assign(perm, perm + lower_.rows());
    out.flops = common_.fl;
    out.entries = common_.lnz;
    cholmod_free_factor(&symbolic, &common_);
    return out;
  }

 private:
  SpMat lower_;
  cholmod_common common_;
  cholmod_sparse view_;
};

// A's pattern with each row replaced by its body's: which bodies each column touches.
SpMat body_pattern(const SpMat& A, const std::vector<int>& body, int bodies) {
  std::vector<int> outer{0}, inner, mark(size_t(bodies), -1);
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const size_t begin = inner.size();
    for (SpMat::InnerIterator it(A, j); it; ++it) {
      const int b = body[size_t(it.row())];
      if (mark[size_t(b)] != int(j)) mark[size_t(b)] = int(j), inner.push_back(b);
    }
    std::sort(inner.begin() + long(begin), inner.end());
    outer.push_back(int(inner.size()));
  }
  const std::vector<double> ones(inner.size(), 1.0);
  return Eigen::Map<const SpMat>(bodies, A.cols(), Eigen::Index(inner.size()), outer.data(),
                                 inner.data(), ones.data());
}

// A's pattern (its rows, each column's rows but for empty columns) and the bodies, hashed: the
// order depends on nothing else.
uint64_t pattern_key(const SpMat& A, const std::vector<int>& body) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over 32-bit words
  auto mix = [&](uint64_t word) {
    h ^= word;
    h *= 1099511628211ull;
  };
  mix(uint64_t(A.rows()));
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    if (A.col(j).nonZeros() == 0) continue;
    mix(0xffffffffull);  // column break
    for (SpMat::InnerIterator it(A, j); it; ++it) mix(uint64_t(it.index()));
  }
  mix(0xfffffffeull);
  for (int b : body) mix(uint64_t(b));
  return h;
}

// Without the cache below.
RowOrder best_row_order(const SpMat& A, const std::vector<int>& body) {
  keep_factorizations_on_this_thread();
  SymbolicAnalysis rows(lower_normal_pattern(A, EntriesByRow(A)));
  // Minimum degree (AMD) on the rows first: a tenth of METIS's time.
  RowOrder best = rows.order(CHOLMOD_AMD);
  best.method = "AMD on the rows";
  bool chain = false;  // nested dissection lost to minimum degree on the bodies
  int bodies = 0;
  for (int b : body) bodies = std::max(bodies, b + 1);
  if (bodies > 0 && bodies < A.rows()) {
    // Both methods on the bodies, a sixth of the nodes and a thirtieth of the edges: METIS there
    // takes about AMD's time on the rows.
    const SpMat Q = body_pattern(A, body, bodies);
    SymbolicAnalysis on_bodies(lower_normal_pattern(Q, EntriesByRow(Q)));
    auto rows_of = std::vector<std::vector<int>>(size_t(bodies));
    for (size_t r = 0; r < body.size(); ++r) rows_of[size_t(body[r])].push_back(int(r));
    auto expanded = [&](int ordering, const char* method) {
      std::vector<int> given;
      for (int b : on_bodies.order(ordering).rows)
        given.insert(given.end(), rows_of[size_t(b)].begin(), rows_of[size_t(b)].end());
      RowOrder o = given.size() == size_t(A.rows()) ? rows.order(CHOLMOD_GIVEN, given) : RowOrder{};
      o.method = method;
      return o;
    };
    RowOrder amd = expanded(CHOLMOD_AMD, "AMD on the bodies"),
             metis = expanded(CHOLMOD_METIS, "METIS on the bodies");
    chain = metis.flops > kChainLike * amd.flops;
    for (RowOrder* o : {&amd, &metis})
      if (o->flops < best.flops) best = std::move(*o);
  }
  // METIS's nested dissection on the rows, where the best factor so far is broad (many flops per
  // stored entry) and not a chain.
  if (!chain && best.flops > kNarrowFactor * best.entries) {
    RowOrder metis = rows.order(CHOLMOD_METIS);
    metis.method = "METIS on the rows";
    if (metis.flops < best.flops) best = std::move(metis);
  }
  if (best.rows.empty()) {  // out of memory: CHOLMOD will say so again
    best.rows.resize(size_t(A.rows()));
    std::iota(best.rows.begin(), best.rows.end(), 0);
  }
  return best;
}

}  // namespace

RowOrder fill_reducing_order(const SpMat& A, const std::vector<int>& body) {
  // The orders found last on this thread, by pattern: a build step's LP orders its normal matrix
  // (and the frictionless LP's, which differs by a row or two, in between), and the spread built
  // from its optimum (load_spread.h) orders the LP's again. A hash that collided would give an
  // order of the same rows, only a poorer one.
  struct Found {
    uint64_t key = 0;
    RowOrder order;
  };
  constexpr size_t kKept = 4;
  thread_local std::vector<Found> found;  // the latest last
  const uint64_t key = pattern_key(A, body);
  for (auto it = found.begin(); it != found.end(); ++it)
    if (it->key == key && it->order.rows.size() == size_t(A.rows())) {
      std::rotate(it, it + 1, found.end());
      return found.back().order;
    }
  if (found.size() == kKept) found.erase(found.begin());
  found.push_back({key, best_row_order(A, body)});
  return found.back().order;
}

struct NormalFactor::Cholmod {
  PivotedLLT llt;
};

NormalFactor::NormalFactor(std::vector<int> order)
    : cholmod_(std::make_unique<Cholmod>()), order_(std::move(order)) {
  keep_factorizations_on_this_thread();
  auto& common = cholmod_->llt.cholmod();
  common.print = 0;  // failures are handled by the caller, not printed
  // NormalMatrix forms the matrix in its fill-reducing order already.
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_NATURAL;
  common.postorder = 0;
}

NormalFactor::~NormalFactor() = default;

void NormalFactor::analyse(const SpMat& lower) {
  cholmod_->llt.analyzePattern(lower);
}

bool NormalFactor::factorize(const SpMat& lower, const Eigen::MatrixXd& dense,
                             const Vec& dense_theta) {
  cholmod_->llt.factorize(lower);
  if (cholmod_->llt.info() != Eigen::Success) return false;
  // With M = L·Lᵀ: M + θ·a·aᵀ = L·(I + θ·z·zᵀ)·Lᵀ, z = L⁻¹·a, and the diagonal plus rank one is
  // factored as L̃·D̃·L̃ᵀ (Gill, Golub, Murray and Saunders' method C1), L̃ = I below the
  // diagonal z_i·β_j; each further column updates D̃ in the same way.
  updates_.clear();
  diagonal_ = Vec::Ones(lower.rows());
  for (Eigen::Index k = 0; k < dense.cols(); ++k) {
    Vec z = to_factor_order(dense.col(k));
    cholmod_->llt.half_solve(CHOLMOD_L, z);
    for (const RankOne& u : updates_) z = u.solve_lower(z);
    Vec beta(z.size());
    double alpha = dense_theta[k];
    for (Eigen::Index j = 0; j < z.size(); ++j) {
      const double d = diagonal_[j], updated = d + alpha * z[j] * z[j];
      beta[j] = alpha * z[j] / updated;
      alpha *= d / updated;
      diagonal_[j] = updated;
    }
    updates_.push_back({std::move(z), std::move(beta)});
  }
  return true;
}

Vec NormalFactor::RankOne::solve_lower(Vec b) const {
  double sum = 0;  // Σ_{j<i} β_j·y_j
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    b[i] -= z[i] * sum;
    sum += beta[i] * b[i];
  }
  return b;
}

Vec NormalFactor::RankOne::solve_upper(Vec c) const {
  double sum = 0;  // Σ_{i>j} z_i·x_i
  for (Eigen::Index j = c.size() - 1; j >= 0; --j) {
    c[j] -= beta[j] * sum;
    sum += z[j] * c[j];
  }
  return c;
}

Vec NormalFactor::solve(const Vec& r) const {
  Vec v = to_factor_order(r);
  cholmod_->llt.half_solve(CHOLMOD_L, v);
  for (const RankOne& u : updates_) v = u.solve_lower(std::move(v));
  v = v.cwiseQuotient(diagonal_);
  for (auto u = updates_.rbegin(); u != updates_.rend(); ++u) v = u->solve_upper(std::move(v));
  cholmod_->llt.half_solve(CHOLMOD_Lt, v);
  return from_factor_order(v);
}

Vec conjugate_gradients(const NormalFactor& factor, const std::function<Vec(const Vec&)>& times,
                        const Vec& r, double relative_target, long& steps) {
  Vec v = factor.solve(r);
  Vec residual = r - times(v);
  const double target = relative_target * r.norm();
  if (residual.norm() <= target) return v;
  Vec z = factor.solve(residual), d = z;
  double rz = residual.dot(z);
  for (int k = 0; k < 50 && residual.norm() > target; ++k) {
    ++steps;
    Vec Md = times(d);
    const double curvature = d.dot(Md);
    if (!(curvature > 0)) break;
    const double alpha = rz / curvature;
    v += alpha * d;
    residual -= alpha * Md;
    if (residual.norm() <= target) break;  // the next direction's solve would go unused
    z = factor.solve(residual);
    const double rz_next = residual.dot(z);
    d = z + (rz_next / rz) * d;
    rz = rz_next;
  }
  return v;
}

Vec NormalFactor::pivots() const {
  return from_factor_order(cholmod_->llt.pivots());
}

Vec NormalFactor::to_factor_order(const Vec& v) const {
  Vec permuted(v.size());
  for (Eigen::Index k = 0; k < v.size(); ++k) permuted[k] = v[order_[size_t(k)]];
  return permuted;
}

Vec NormalFactor::from_factor_order(const Vec& v) const {
  Vec original(v.size());
  for (Eigen::Index k = 0; k < v.size(); ++k) original[order_[size_t(k)]] = v[k];
  return original;
}

}  // namespace lego::physics
