#include "physics/load_spread.h"

#include <algorithm>
#include <cmath>

#include "physics/normal_equations.h"

namespace lego::physics {
namespace {

using Vec = Eigen::VectorXd;

// Θ_j⁻¹ = Σ over its bounds of (r·s + μ) / s², s the force's slack to a bound and r the part of
// its reduced cost that points at that bound, both relative (s to T, r to the largest reduced
// cost): the interior point method's z/s per bound, with z = r + μ/s. At a bound the optimum
// holds a force to, Θ is about s/r; where the reduced cost vanishes, s²/μ: small at a bound
// (forces at zero that cost nothing, degenerate at the optimum: weighed s/r alone, they were the
// freest of all and pulled by a gram-force within three steps) and large between. The slacks are
// those of the forces the step begins from, not the LP's: with the LP's, a normal force of 1.3 gf
// went 1.3 -> 0.19 -> -0.12 gf in three steps. Support forces are free.
constexpr double kMu = 1e-8;

// Slacks below this (relative to T) count as this: at zero Θ would be zero, and a body whose
// forces all sit at bounds an empty row of the normal matrix, which no relative shift mends.
constexpr double kLeastSlack = 1e-12;

// Θ, relative, no smaller than this: with kLeastSlack a force at its bound weighs 1e-16 against
// the free supports' 1e8 to 1e10, a condition of 1e26, and a load that only such columns could
// take had the conjugate gradients diverge. With it, on legolize's duck at height 40
// (docs/performance.md, 2026-12-07), 7 steps went to the LP instead of 10; 1e-6 and 1e-10 measured
// about as well on the duck and the bunny, neither better on both.
constexpr double kLeastTheta = 1e-8;

double barrier(double slack, double toward) {  // relative slack, reduced cost toward it
  slack = std::max(slack, kLeastSlack);
  return (toward * slack + kMu) / (slack * slack);
}

// The conjugate gradients stop at this relative residual: what is left is far inside the
// certificate's check (1e-6 of the largest force), and 1e-12 took three solves where this takes
// one or two. A second pass, for what columns whose values differ a little from the solved
// step's leave (a knob's grip shared with a new brick), only where the first leaves more than
// this share of the load: on the duck at height 40 it left 1e-11 to 1e-8 of it.
constexpr double kSpreadAccuracy = 1e-10;
constexpr double kSecondPass = 1e-9;

}  // namespace

struct LoadSpread::Solved {
  std::vector<ForceKind> kind;  // per column
  std::vector<double> reduced;  // the LP's reduced costs, relative to the largest
  int rows = 0;                 // of the normal matrix
  std::vector<int> row_map;     // the solved step's row -> its row there, or -1
  SparseMatrix A;               // on those rows
  std::unordered_map<uint64_t, int> column_of_key;
  std::unique_ptr<NormalMatrix> normal;
  std::unique_ptr<NormalFactor> factor;

  // Adds to x the least-Θ-norm forces on these columns (`column`: each one's column of s, or -1)
  // that balance these bodies (`body_of`: each body of s its body here, or -1); false when the
  // matrix cannot be factored.
  bool balance(const EquilibriumSystem& s, const std::vector<int>& body_of,
               const std::vector<int>& column, const Vec& theta, std::vector<double>& x);
};

LoadSpread::LoadSpread(const EquilibriumSystem& s, const std::vector<uint64_t>& column_keys,
                       const std::vector<int>& body_bricks, const std::vector<double>& row_duals,
                       double cm)
    : solved_(std::make_unique<Solved>()), solved_cm_(cm) {
  if (row_duals.size() != size_t(s.rows)) return;
  Solved& v = *solved_;
  v.kind = s.kind;
  v.reduced.resize(size_t(s.columns()));
  double largest = 1e-300;
  for (int j = 0; j < s.columns(); ++j) {
    double rc = 0;  // c − Aᵀy, c = 0 on every force column of the scaled form
    for (int e = s.column_start[size_t(j)]; e < s.column_start[size_t(j) + 1]; ++e)
      rc -= s.value[size_t(e)] * row_duals[size_t(s.row_index[size_t(e)])];
    v.reduced[size_t(j)] = rc;
    largest = std::max(largest, std::abs(rc));
  }
  for (double& rc : v.reduced) rc /= largest;
  for (int j = 0; j < s.columns(); ++j) v.column_of_key.emplace(column_keys[size_t(j)], j);
  for (size_t b = 0; b < body_bricks.size(); ++b) body_of_brick_.emplace(body_bricks[b], int(b));
  // Rows no force reaches stay out: the normal matrix would have an empty row.
  v.row_map.assign(size_t(s.rows), -1);
  for (size_t e = 0; e < s.row_index.size(); ++e)
    if (s.value[e] != 0) v.row_map[size_t(s.row_index[e])] = 0;
  std::vector<int> body;
  for (int r = 0; r < s.rows; ++r)
    if (v.row_map[size_t(r)] == 0) {
      v.row_map[size_t(r)] = v.rows++;
      body.push_back(EquilibriumSystem::body_of_row(r));
    }
  v.A = renumber_rows(v.rows, s.columns(), s.column_start.data(), s.row_index.data(),
                      s.value.data(), v.row_map);
  const RowOrder order = fill_reducing_order(v.A, body);
  if (order.rows.empty()) return;
  v.normal = std::make_unique<NormalMatrix>(v.A, order.rows);
  v.factor = std::make_unique<NormalFactor>(order.rows);
  v.factor->analyse(v.normal->form(Vec::Ones(s.columns()), 0.0));
  usable_ = true;
}

LoadSpread::~LoadSpread() = default;

int LoadSpread::body_of_brick(int whole) const {
  const auto it = body_of_brick_.find(whole);
  return it == body_of_brick_.end() ? -1 : it->second;
}

bool LoadSpread::spread(const EquilibriumSystem& s, const std::vector<uint64_t>& column_keys,
                        const std::vector<int>& body_of, std::vector<double>& x) const {
  if (!usable_) return false;
  Solved& v = *solved_;
  const size_t n = v.kind.size();
  std::vector<int> column(n, -1);  // per column here, its column of s
  for (int j = 0; j < s.columns(); ++j)
    if (const auto it = v.column_of_key.find(column_keys[size_t(j)]); it != v.column_of_key.end())
      column[size_t(it->second)] = j;
  // Friction's upper bound is T, where the certificate's is: bounded by the LP's largest friction
  // (what C_M was), the frictions that set C_M could not rise with the load, and four steps of
  // the duck at height 24 were certified, against eighteen with T.
  Vec theta(static_cast<Eigen::Index>(n));
  for (size_t j = 0; j < n; ++j) {
    const double f = (column[j] >= 0 ? x[size_t(column[j])] : 0.0) / kMaxFrictionLoad;
    const double rc = v.reduced[j];
    double inverse = kMu;  // a free force: the freest
    if (v.kind[j] == ForceKind::Friction)
      inverse = barrier(f, std::max(rc, 0.0)) + barrier(1 - f, std::max(-rc, 0.0));
    else if (v.kind[j] == ForceKind::Normal)
      inverse = barrier(f, std::max(rc, 0.0));
    theta[Eigen::Index(j)] = std::max(1 / inverse, kLeastTheta);
  }
  const std::lock_guard<std::mutex> lock(factoring_);
  return v.balance(s, body_of, column, theta, x);
}

bool LoadSpread::Solved::balance(const EquilibriumSystem& s, const std::vector<int>& body_of,
                                 const std::vector<int>& column, const Vec& theta,
                                 std::vector<double>& x) {
  // Rows that depend on others (a body held at one point) make the matrix singular: a shift of
  // the diagonal, relative to it, and the conjugate gradients below remove the difference.
  bool factored = false;
  for (double shift = 1e-12; shift <= 1e-4 && !factored; shift *= 100)
    factored = factor->factorize(normal->form(theta, shift), Eigen::MatrixXd(rows, 0), Vec());
  if (!factored) return false;
  auto times_normal = [&](const Vec& u) -> Vec {
    return A * theta.cwiseProduct(A.transpose() * u);
  };
  constexpr int kRows = EquilibriumSystem::kEquations;
  double first = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<double> residual = s.unbalanced(x);
    Vec r = Vec::Zero(rows);
    for (size_t b = 0; b < body_of.size(); ++b)
      if (body_of[b] >= 0)
        for (int k = 0; k < kRows; ++k)
          if (const int here = row_map[size_t(EquilibriumSystem::row(body_of[b], k))]; here >= 0)
            r[here] = residual[size_t(EquilibriumSystem::row(int(b), k))];
    const double left = r.lpNorm<Eigen::Infinity>();
    if (pass == 0) first = left;
    if (left == 0 || (pass > 0 && left <= kSecondPass * first)) break;
    long steps = 0;
    const Vec y = conjugate_gradients(*factor, times_normal, r, kSpreadAccuracy, steps);
    const Vec dx = theta.cwiseProduct(A.transpose() * y);
    for (size_t j = 0; j < kind.size(); ++j)
      if (column[j] >= 0) x[size_t(column[j])] += dx[Eigen::Index(j)];
  }
  return true;
}

}  // namespace lego::physics
