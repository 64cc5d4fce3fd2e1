#include "physics/certificate.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include <fmt/format.h>

#include "physics/clp_lp.h"

namespace lego::physics {
namespace {

using Load = Eigen::Matrix<double, 6, 1>;
constexpr int kNone = -1;
constexpr int kUnreached = std::numeric_limits<int>::max();

// Who each column joins: one body (the other side is the ground or a fixed part) or two.
struct ColumnBodies {
  int first = kNone, second = kNone;
  int other_than(int body) const { return first == body ? second : first; }
};

std::vector<ColumnBodies> bodies_of_columns(const EquilibriumSystem& s) {
  std::vector<ColumnBodies> out(static_cast<size_t>(s.columns()));
  for (int j = 0; j < s.columns(); ++j)
    for (int k = s.column_start[size_t(j)]; k < s.column_start[size_t(j) + 1]; ++k) {
      const int body = EquilibriumSystem::body_of_row(s.row_index[size_t(k)]);
      ColumnBodies& c = out[size_t(j)];
      if (c.first == kNone)
        c.first = body;
      else if (c.first != body)
        c.second = body;
    }
  return out;
}

// Whether a column's contact can carry a weight: knobs, joints and faces one on top of the other
// can; faces side by side only push across.
std::vector<char> carrying_columns(const EquilibriumSystem& s, const ContactGraph& graph) {
  std::vector<char> out(static_cast<size_t>(s.columns()));
  for (int j = 0; j < s.columns(); ++j) {
    const Contact& c = graph.contacts[size_t(s.contact[size_t(j)])];
    out[size_t(j)] = c.snap() || c.joint || c.turned || axis_of(c.direction) == 1;
  }
  return out;
}

// Carrying contacts from the ground, breadth first: a body passes its load to bodies nearer.
std::vector<int> distance_from_ground(int bodies, const std::vector<ColumnBodies>& columns,
                                      const std::vector<char>& carrying,
                                      const std::vector<std::vector<int>>& body_columns) {
  std::vector<int> distance(static_cast<size_t>(bodies), kUnreached), queue;
  for (size_t j = 0; j < columns.size(); ++j) {
    const ColumnBodies& c = columns[j];
    if (carrying[j] && c.first != kNone && c.second == kNone &&
        distance[size_t(c.first)] == kUnreached) {
      distance[size_t(c.first)] = 0;
      queue.push_back(c.first);
    }
  }
  for (size_t q = 0; q < queue.size(); ++q) {
    const int b = queue[q];
    for (int j : body_columns[size_t(b)]) {
      if (!carrying[size_t(j)]) continue;
      const int other = columns[size_t(j)].other_than(b);
      if (other != kNone && distance[size_t(other)] == kUnreached) {
        distance[size_t(other)] = distance[size_t(b)] + 1;
        queue.push_back(other);
      }
    }
  }
  return distance;
}

// rows -= amount · (column of A): the rows a force of `amount` on the column leaves unbalanced.
void subtract_column(const EquilibriumSystem& s, int column, double amount,
                     std::vector<double>& rows) {
  for (int e = s.column_start[size_t(column)]; e < s.column_start[size_t(column) + 1]; ++e)
    rows[size_t(s.row_index[size_t(e)])] -= s.value[size_t(e)] * amount;
}

Load column_on(const EquilibriumSystem& s, int column, int body) {
  Load a = Load::Zero();
  for (int k = s.column_start[size_t(column)]; k < s.column_start[size_t(column) + 1]; ++k) {
    const int row = s.row_index[size_t(k)];
    if (EquilibriumSystem::body_of_row(row) == body)
      a[row - EquilibriumSystem::row(body, 0)] += s.value[size_t(k)];
  }
  return a;
}

// Passes over the model, each after a body that failed is hung from its neighbours: a pass costs
// a tenth of the LP or less. With one pass, Bunde nog Kanden had 26 of its 48 steps certified
// (5.3 s with the LP for the others), with 8 passes 45 (1.5 s); 24 passes added one step of the
// bunny's 44 at a tenth more time.
constexpr int kPasses = 8;

// A body's rows balanced to this fraction of the largest load are not passed on: 1e-12 had
// every body of a step begun from the LP's forces pass on its rounding (2,700 small LPs for a
// bunny's 30 new bricks).
constexpr double kBalanced = 1e-9;

// How far (in contacts) the bodies that share a load a body cannot pass on alone reach.
constexpr int kWindowHops = 2;
// Shared loads cost a larger LP each (tens of bodies): a certificate that needs more is left
// to the whole model's LP.
constexpr int kMaxWindows = 32;

// A body's largest friction that leaves ample margin for what is passed on below it.
constexpr double kAmpleFriction = 0.25 * kMaxFrictionLoad;

double tolerance_for(const Load& load) {
  return 1e-7 * (load.norm() + 1.0);
}

// Support forces (and joints) cost far more than pushes: taken for what pushes cannot hold (a
// push across, a twist), never to level a weight, or their sideways forces pile up below (a
// weight levelled by a 1x1's support twisted the 1x1 under it, which one knob cannot hold).
double weight(ForceKind kind) {
  return kind == ForceKind::Support ? 1e-4 : 1.0;
}

// The least-squares forces that pass `load` on without friction, added to `base`; false when
// a push would pull.
bool pass_on_pushing(const std::vector<Load>& a, const std::vector<ForceKind>& kind,
                     const std::vector<double>& base, const Load& load, std::vector<double>& x) {
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  for (size_t j = 0; j < a.size(); ++j)
    if (kind[j] != ForceKind::Friction) m += weight(kind[j]) * a[j] * a[j].transpose();
  m.diagonal().array() += 1e-12 * (m.trace() + 1.0);
  const Load y = m.ldlt().solve(load);
  Load passed = Load::Zero();
  x.assign(a.size(), 0.0);
  for (size_t j = 0; j < a.size(); ++j) {
    if (kind[j] == ForceKind::Friction) continue;
    x[j] = weight(kind[j]) * a[j].dot(y);
    if (kind[j] == ForceKind::Normal && base[j] + x[j] < 0) return false;
    passed += a[j] * x[j];
  }
  return (passed - load).norm() <= tolerance_for(load);
}

// The forces on `columns` that balance the rows of the bodies `window` leaves unbalanced, added
// to `x`, with the least largest friction: min t, A_W·dx = unbalanced_W, x_f + dx_f ≤ t, x + dx
// within the bounds. Rows of bodies outside the window are not held: the caller gives only
// columns whose other body may take what they pass on.
bool pass_on_least_friction(const EquilibriumSystem& s, const std::vector<int>& window,
                            const std::vector<int>& columns, const std::vector<double>& x,
                            const std::vector<double>& unbalanced, std::vector<double>& dx,
                            double& largest_friction) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  // A little cost on what is passed beyond the largest friction: with none, the LP leaves
  // support forces at any value its vertex happens to have, and their twists pile up below.
  constexpr double kPassing = 1e-3;
  constexpr int kRows = EquilibriumSystem::kEquations;
  LpData lp;
  lp.rows = int(window.size()) * kRows;
  std::vector<std::pair<int, double>> entries;
  auto entries_of = [&](int j, double sign) {
    entries.clear();
    for (int e = s.column_start[size_t(j)]; e < s.column_start[size_t(j) + 1]; ++e) {
      // The window is one body or a few tens: its place in it is found by looking.
      const int row = s.row_index[size_t(e)];
      const auto at = std::find(window.begin(), window.end(), EquilibriumSystem::body_of_row(row));
      if (at != window.end() && s.value[size_t(e)] != 0)
        entries.emplace_back(int(at - window.begin()) * kRows + row % kRows,
                             sign * s.value[size_t(e)]);
    }
  };
  std::vector<double> friction_upper;
  for (int j : columns) {
    const double b = x[size_t(j)];
    switch (s.kind[size_t(j)]) {
      case ForceKind::Friction:
        entries_of(j, 1);
        entries.emplace_back(lp.rows + int(friction_upper.size()), 1.0);
        friction_upper.push_back(-b);
        lp.add_column(-b, kMaxFrictionLoad - b, kPassing, entries);
        break;
      case ForceKind::Normal:
        entries_of(j, 1);
        lp.add_column(-b, inf, 0.0, entries);
        break;
      case ForceKind::Support:  // free: as a pair of columns, each way
        entries_of(j, 1);
        lp.add_column(0.0, inf, kPassing, entries);
        entries_of(j, -1);
        lp.add_column(0.0, inf, kPassing, entries);
        break;
    }
  }
  std::vector<std::pair<int, double>> t_entries;
  for (size_t r = 0; r < friction_upper.size(); ++r) t_entries.emplace_back(lp.rows + int(r), -1.0);
  lp.add_column(0.0, kMaxFrictionLoad, 1.0, t_entries);
  for (int b : window)
    for (int r = 0; r < kRows; ++r) {
      const double load = unbalanced[size_t(EquilibriumSystem::row(b, r))];
      lp.row_lower.push_back(load);
      lp.row_upper.push_back(load);
    }
  lp.rows += int(friction_upper.size());
  for (double u : friction_upper) {
    lp.row_lower.push_back(-inf);
    lp.row_upper.push_back(u);
  }
  // Unscaled: the rows are forces and moments of one body, alike in size; and Clp's scaling
  // called some of these feasible problems infeasible (a body on two single knobs, a twist).
  const LpSolution solution = solve_lp(lp, LpMethod::DualSimplex, false, false, 1.0);
  if (solution.outcome != LpOutcome::Optimal) return false;
  largest_friction = solution.x.back();
  dx.assign(columns.size(), 0.0);
  for (size_t k = 0, column = 0; k < columns.size(); ++k) {
    const int j = columns[k];
    dx[k] = solution.x[column++];
    if (s.kind[size_t(j)] == ForceKind::Support)
      dx[k] -= solution.x[column++];
    else  // within the bounds: Clp keeps them to 1e-7, the rows then balanced to as much
      dx[k] = std::clamp(dx[k], -x[size_t(j)],
                         s.kind[size_t(j)] == ForceKind::Friction
                             ? kMaxFrictionLoad - x[size_t(j)]
                             : std::numeric_limits<double>::infinity());
  }
  return true;
}

bool past_bound(const EquilibriumSystem& s, int j, double v, double scale) {
  switch (s.kind[size_t(j)]) {
    case ForceKind::Support:
      return false;
    case ForceKind::Normal:
      return v < -1e-9 * scale;
    case ForceKind::Friction:
      return v < -1e-9 * scale || v >= kMaxFrictionLoad;
  }
  return false;
}

// Forces found for the whole model changed near one column: the columns between its two bodies
// alone (they act on the two as opposite loads, so balancing one balances the other: an LP on six
// rows), else every column among the bodies within `reach` contacts of them and to the ground,
// their rows held. Each LP keeps every row as balanced as it was, brings the columns it frees
// within their bounds, and least raises the largest friction among them.
class Neighbourhood {
 public:
  Neighbourhood(const EquilibriumSystem& s, const std::vector<ColumnBodies>& columns,
                const std::vector<std::vector<int>>& body_columns, std::vector<double>& x)
      : s_(s),
        columns_(columns),
        body_columns_(body_columns),
        x_(x),
        unbalanced_(s.unbalanced(x)),
        hops_(static_cast<size_t>(s.rows / EquilibriumSystem::kEquations), -1) {}

  // Changes the forces near column j, within `reach` contacts (0: between its bodies alone);
  // false when the LP finds none. `largest`: the largest friction among the columns it freed.
  bool change_around(int j, int reach, double& largest) {
    const ColumnBodies pair = columns_[size_t(j)];
    if (pair.first == kNone) return false;
    window_.assign(1, pair.first);
    free_.clear();
    if (reach == 0) {
      for (int k : body_columns_[size_t(pair.first)])
        if (columns_[size_t(k)].other_than(pair.first) == pair.other_than(pair.first))
          free_.push_back(k);
    } else {
      hops_[size_t(pair.first)] = 0;
      if (pair.second != kNone) {
        hops_[size_t(pair.second)] = 0;
        window_.push_back(pair.second);
      }
      for (size_t q = 0; q < window_.size(); ++q) {
        const int w = window_[q];
        if (hops_[size_t(w)] == reach) continue;
        for (int k : body_columns_[size_t(w)])
          if (const int other = columns_[size_t(k)].other_than(w);
              other != kNone && hops_[size_t(other)] < 0) {
            hops_[size_t(other)] = hops_[size_t(w)] + 1;
            window_.push_back(other);
          }
      }
      for (int w : window_)
        for (int k : body_columns_[size_t(w)]) {
          const int other = columns_[size_t(k)].other_than(w);
          if (other == kNone || (hops_[size_t(other)] >= 0 && other > w)) free_.push_back(k);
        }
      for (int w : window_) hops_[size_t(w)] = -1;
    }
    ++lps;
    if (!pass_on_least_friction(s_, window_, free_, x_, unbalanced_, dx_, largest)) return false;
    for (size_t k = 0; k < free_.size(); ++k) {
      x_[size_t(free_[k])] += dx_[k];
      subtract_column(s_, free_[k], dx_[k], unbalanced_);
    }
    return true;
  }

  int lps = 0;

 private:
  const EquilibriumSystem& s_;
  const std::vector<ColumnBodies>& columns_;
  const std::vector<std::vector<int>>& body_columns_;
  std::vector<double>& x_;
  std::vector<double> unbalanced_, dx_;
  std::vector<int> hops_, window_, free_;
};

// Forces a spread leaves past a bound: on the duck at height 40 (brickcheck --steps, 222 steps)
// 98 of 184 spreads left some, most a few, a fraction of a gram-force past; brought back here in
// 0.7 s in all. The spread's own rounds that weighted them down and factored again (three) still
// failed 25 times, each then an LP: 59 s against 29 s (docs/performance.md, 2026-12-07). Within
// three contacts instead of two: more time, no fewer LPs.
constexpr int kMendReach = 2;
constexpr size_t kMostMended = 256;  // a few spreads leave hundreds: those go to the LP

// Brings every force past a bound within it; false when there are too many or no LP near one
// finds forces.
bool mend(const EquilibriumSystem& s, const std::vector<ColumnBodies>& columns,
          const std::vector<std::vector<int>>& body_columns, double scale, std::vector<double>& x,
          Certificate& out) {
  std::vector<int> past;
  for (int j = 0; j < s.columns() && past.size() <= kMostMended; ++j)
    if (past_bound(s, j, x[size_t(j)], scale)) past.push_back(j);
  if (past.empty()) return true;
  if (past.size() > kMostMended) return false;
  Neighbourhood near(s, columns, body_columns, x);
  bool mended = true;
  for (int j : past) {
    double largest = 0;
    bool within = !past_bound(s, j, x[size_t(j)], scale);  // mended with one before
    for (int reach = 0; reach <= kMendReach && !within; ++reach)
      within = near.change_around(j, reach, largest);
    if (!within) {
      mended = false;
      break;
    }
  }
  out.local_lps += near.lps;
  out.mended = int(past.size());
  return mended;
}

// The largest friction lowered, one column at a time, while the bound is under `wanted`: the
// sweep and the spread each balance loads without looking at the largest friction they leave,
// and a step certified well under its C_M goes to the LP (step_stability.h). 24 instead of 8
// certified no more steps of the duck at height 40.
constexpr int kLowerings = 8;

void lower_largest_friction(const EquilibriumSystem& s, const std::vector<ColumnBodies>& columns,
                            const std::vector<std::vector<int>>& body_columns, double wanted,
                            std::vector<double>& x, int& local_lps) {
  std::optional<Neighbourhood> near;  // made when first needed: it costs a pass over the system
  for (int round = 0; round < kLowerings; ++round) {
    int top = kNone;
    for (int j = 0; j < s.friction_columns; ++j)
      if (top == kNone || x[size_t(j)] > x[size_t(top)]) top = j;
    if (top == kNone || kMaxFrictionLoad - x[size_t(top)] >= wanted) break;
    if (!near) near.emplace(s, columns, body_columns, x);
    const double before = x[size_t(top)];
    double largest = before;
    if (!near->change_around(top, kMendReach, largest) || largest >= before * (1 - 1e-6)) break;
  }
  if (near) local_lps += near->lps;
}

// The check, from the system alone: A·x = b on every row, every force within its bounds. Found,
// with C_M and the forces, or why not.
void check_forces(const EquilibriumSystem& s, double scale, std::vector<double> x,
                  Certificate& out) {
  const std::vector<double> residual = s.unbalanced(x);
  // Clp's small LPs balance each row to 1e-7 of its own forces; passed down many bodies, the
  // rounding reaches 1e-6 of the largest force (3e-4 g·m/s² on a bunny of 3,000 bricks).
  double worst = 0.0, largest_friction = 0.0, largest_force = scale;
  for (double r : residual) worst = std::max(worst, std::abs(r));
  for (double v : x) largest_force = std::max(largest_force, std::abs(v));
  if (worst > 1e-6 * largest_force) {
    out.why_not = fmt::format("the forces leave {:.3g} unbalanced", worst);
    return;
  }
  for (int j = 0; j < s.columns(); ++j) {
    const double v = x[size_t(j)];
    if (s.kind[size_t(j)] == ForceKind::Support) continue;
    if (v < -1e-9 * scale) {
      out.why_not = fmt::format("a force pulls where it can only push ({:.3g})", v);
      return;
    }
    if (s.kind[size_t(j)] == ForceKind::Friction) largest_friction = std::max(largest_friction, v);
  }
  if (largest_friction >= kMaxFrictionLoad) {
    out.why_not = "a friction force reaches T";
    return;
  }
  out.found = true;
  out.cm = kMaxFrictionLoad - largest_friction;
  out.forces = std::move(x);
}

}  // namespace

// One function of ~150 lines, for a reason: the sweep, the shared LPs around a body that cannot
// pass its load on alone, and the passes that hang a failed body from its neighbours all read
// and change one order of the bodies, their ranks, the forces so far and what is left
// unbalanced.
Certificate certify(const EquilibriumSystem& s, const ContactGraph& graph,
                    const std::vector<double>& start, const Spreading* spreading,
                    double wanted_cm) {
  Certificate out;
  const int bodies = s.rows / EquilibriumSystem::kEquations;
  // Bodies the spreading takes the loads of: the sweep passes loads on to them at any rank.
  auto spread_body = [&](int b) { return spreading && spreading->bodies[size_t(b)]; };
  const std::vector<ColumnBodies> columns = bodies_of_columns(s);
  std::vector<std::vector<int>> body_columns(static_cast<size_t>(bodies));
  for (int j = 0; j < s.columns(); ++j) {
    const ColumnBodies& c = columns[size_t(j)];
    if (c.first != kNone) body_columns[size_t(c.first)].push_back(j);
    if (c.second != kNone) body_columns[size_t(c.second)].push_back(j);
  }
  const std::vector<char> carrying = carrying_columns(s, graph);
  std::vector<int> distance = distance_from_ground(bodies, columns, carrying, body_columns);
  // Farthest first; a body passes its load on through its contacts with bodies later in this
  // order and the ground.
  std::vector<int> order(static_cast<size_t>(bodies)), rank(static_cast<size_t>(bodies));
  auto sort_bodies = [&] {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int x, int y) {
      return distance[size_t(x)] != distance[size_t(y)] ? distance[size_t(x)] > distance[size_t(y)]
                                                        : x > y;
    });
    for (int k = 0; k < bodies; ++k) rank[size_t(order[size_t(k)])] = k;
  };
  sort_bodies();

  double scale = 1.0;
  for (double v : s.rhs) scale = std::max(scale, std::abs(v));
  std::vector<double> x, unbalanced;
  std::vector<Load> a;
  std::vector<ForceKind> kind;
  std::vector<int> local, chosen;
  std::vector<double> base, local_x, candidate;
  std::vector<char> hung(static_cast<size_t>(bodies), 0);

  // When a body cannot pass its load on alone, the bodies near it already passed on share it:
  // one LP over them, their rows held balanced, passing on to bodies not yet passed on and the
  // ground (a cantilever's load goes up into the brick that clamps it, and down its other side).
  // Sets `local` and `local_x`.
  std::vector<int> window, hops(static_cast<size_t>(bodies), -1);
  int windows = 0;
  auto pass_on_around = [&](int b) {
    if (++windows > kMaxWindows) return false;
    window.assign(1, b);
    hops[size_t(b)] = 0;
    for (size_t q = 0; q < window.size(); ++q) {
      const int w = window[q];
      if (hops[size_t(w)] == kWindowHops) continue;
      for (int j : body_columns[size_t(w)]) {
        const int other = columns[size_t(j)].other_than(w);
        if (other != kNone && hops[size_t(other)] < 0 && !spread_body(other) &&
            rank[size_t(other)] < rank[size_t(b)]) {
          hops[size_t(other)] = hops[size_t(w)] + 1;
          window.push_back(other);
        }
      }
    }
    local.clear();
    for (int w : window)
      for (int j : body_columns[size_t(w)]) {
        const int other = columns[size_t(j)].other_than(w);
        const bool inside = other != kNone && hops[size_t(other)] >= 0;
        if (inside && other < w) continue;  // listed from the other body
        if (other == kNone || inside || spread_body(other) || rank[size_t(other)] > rank[size_t(b)])
          local.push_back(j);
      }
    for (int w : window) hops[size_t(w)] = -1;
    ++out.local_lps;
    double t = 0;
    return pass_on_least_friction(s, window, local, x, unbalanced, local_x, t);
  };

  // One pass from the farthest body down; the body that cannot pass its load on, or -1.
  auto sweep = [&]() -> int {
    x = start;
    x.resize(size_t(s.columns()), 0.0);
    unbalanced = s.unbalanced(x);
    for (int b : order) {
      if (spread_body(b)) continue;
      if (distance[size_t(b)] == kUnreached) return b;
      const Load load = Eigen::Map<const Load>(&unbalanced[size_t(EquilibriumSystem::row(b, 0))]);
      // Balanced as it started, to well within the check below (the LP's forces to 1e-9 or so).
      if (load.lpNorm<Eigen::Infinity>() <= kBalanced * scale) continue;
      // Pushing down first, through carrying contacts to the ground and bodies nearer it, with
      // least squares; then the LP through every carrying contact with a body not yet passed on;
      // then, when that needs much friction or none is found, through faces side by side too:
      // the end faces of two 1x8s under a 1x2 push on each other as its knobs pull (the paper's
      // figure 7 (b): a tenth of C_M without them), but a push sideways twists what it pushes,
      // and a brick on one knob cannot hold a twist.
      bool passed = false;
      double least = std::numeric_limits<double>::infinity();
      for (int reach : {0, 1, 2}) {
        local.clear();
        a.clear();
        kind.clear();
        base.clear();
        for (int j : body_columns[size_t(b)]) {
          const int other = columns[size_t(j)].other_than(b);
          if (other != kNone && !spread_body(other) && rank[size_t(other)] < rank[size_t(b)])
            continue;  // passed on
          const bool down = carrying[size_t(j)] &&
                            (other == kNone || distance[size_t(other)] < distance[size_t(b)]);
          if ((reach == 0 && !down) || (reach == 1 && !carrying[size_t(j)])) continue;
          local.push_back(j);
          a.push_back(column_on(s, j, b));
          kind.push_back(s.kind[size_t(j)]);
          base.push_back(x[size_t(j)]);
        }
        if (reach == 0) {
          if ((passed = pass_on_pushing(a, kind, base, load, local_x))) break;
          continue;
        }
        ++out.local_lps;
        double t = 0;
        if (pass_on_least_friction(s, {b}, local, x, unbalanced, candidate, t) && t < least) {
          least = t;
          chosen = local;
          local_x.swap(candidate);
          passed = true;
        }
        if (passed && least <= kAmpleFriction) break;
      }
      if (passed && !chosen.empty()) local.swap(chosen);
      chosen.clear();
      if (!passed) passed = pass_on_around(b);
      if (!passed) return b;
      for (size_t k = 0; k < local.size(); ++k) {
        x[size_t(local[k])] += local_x[k];
        subtract_column(s, local[k], local_x[k], unbalanced);
      }
    }
    return -1;
  };
  // A body that fails is passed on before its neighbours in the next pass, so that it hangs from
  // them as well (a cantilever clamped by a brick above that reaches back over its support). On
  // the bunny at height 40, begun from no forces, this certified steps 7 to 10, each after about
  // six passes, as the failure moved up a chain of overhangs.
  for (int pass = 0;; ++pass) {
    const int failed = sweep();
    if (failed < 0) break;
    const size_t f = size_t(failed);
    if (pass + 1 >= kPasses || hung[f] || distance[f] == kUnreached) {
      out.why_not = distance[f] == kUnreached
                        ? "a body reaches no ground through its contacts"
                        : fmt::format("body {} cannot pass its load on within the limits", failed);
      return out;
    }
    hung[f] = 1;
    for (int j : body_columns[f]) {
      const int other = columns[size_t(j)].other_than(failed);
      if (carrying[size_t(j)] && other != kNone)
        distance[f] = std::max(distance[f], distance[size_t(other)] + 1);
    }
    sort_bodies();
  }

  if (spreading && !spreading->spread(x)) {
    out.why_not = "the spread of the LP's forces could not be factored";
    return out;
  }
  if (spreading && !mend(s, columns, body_columns, scale, x, out)) {
    out.why_not = "the spread leaves forces past their bounds that no LP near them brings back";
    return out;
  }
  if (wanted_cm > 0) lower_largest_friction(s, columns, body_columns, wanted_cm, x, out.local_lps);
  check_forces(s, scale, std::move(x), out);
  return out;
}

}  // namespace lego::physics
