#include "physics/local_bounds.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>

#include "core/stopwatch.h"
#include "physics/scaled_lp.h"

namespace lego::physics {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

using BrickKey = std::array<int, 6>;  // lattice position, footprint and height: the physics of it
BrickKey key_of(const Brick& b) {
  return {b.min.x, b.min.y, b.min.z, b.size_x(), b.size_z(), b.height()};
}

// A column's identity across two systems: its contact (a snap or a face, its direction, by the two
// bricks' indices in `before`), its kind, and its place among the columns of that contact and kind
// (build_equilibrium orders them by the contact's geometry alone).
using ColumnKey = std::array<int, 6>;

class ColumnKeys {
 public:
  // `brick` maps the system's brick indices to those the keys use (negative: none, no key).
  ColumnKeys(const EquilibriumSystem& sys, const ContactGraph& g, const std::vector<int>& brick) {
    std::map<std::pair<int, int>, int> ordinal;
    keys_.resize(size_t(sys.columns()));
    valid_.resize(size_t(sys.columns()));
    for (int j = 0; j < sys.columns(); ++j) {
      const int contact = sys.contact[size_t(j)];
      const int n = ordinal[{contact, int(sys.kind[size_t(j)])}]++;
      bool valid = true;
      auto map = [&](int b) {
        if (b == kGround) return kGround;
        valid = valid && brick[size_t(b)] >= 0;
        return brick[size_t(b)];
      };
      const Contact& c = g.contacts[size_t(contact)];
      const int a = map(c.lower), b = map(c.upper), axis = c.direction, side = c.snap() ? 0 : 1;
      valid_[size_t(j)] = valid;
      keys_[size_t(j)] = {side, a, b, axis, int(sys.kind[size_t(j)]), n};
    }
  }
  bool valid(int j) const { return valid_[size_t(j)]; }
  const ColumnKey& operator[](int j) const { return keys_[size_t(j)]; }

 private:
  std::vector<ColumnKey> keys_;
  std::vector<char> valid_;
};

// The bounds take a body for a brick: assemblies with fixed bricks or assumed joints (read from
// LDraw, never refined) are left to the whole analysis.
bool one_body_per_brick(const EquilibriumSystem& sys) {
  for (size_t i = 0; i < sys.body_of.size(); ++i)
    if (sys.body_of[i] != int(i)) return false;
  return true;
}

// The bricks a column's rows belong to (one or two; the ground has no rows).
std::vector<std::vector<int>> bricks_of_columns(const EquilibriumSystem& sys) {
  std::vector<std::vector<int>> out(size_t(sys.columns()));
  for (int j = 0; j < sys.columns(); ++j)
    for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k) {
      const int brick = EquilibriumSystem::body_of_row(sys.row_index[size_t(k)]);
      if (std::find(out[size_t(j)].begin(), out[size_t(j)].end(), brick) == out[size_t(j)].end())
        out[size_t(j)].push_back(brick);
    }
  return out;
}

// The rows of the region's bricks as a system of their own: `columns` (of `sys`) restricted to
// those rows, and b of those rows minus the fixed columns' forces.
EquilibriumSystem region_system(const EquilibriumSystem& sys, const std::vector<int>& region_row,
                                int region_rows, const std::vector<int>& columns,
                                const std::vector<int>& fixed, const std::vector<double>& force) {
  EquilibriumSystem out;
  out.rows = region_rows;
  out.rhs.assign(size_t(region_rows), 0.0);
  for (int r = 0; r < sys.rows; ++r)
    if (region_row[size_t(r)] >= 0) out.rhs[size_t(region_row[size_t(r)])] = sys.rhs[size_t(r)];
  // The analysed forces balance the outside only to the solver's tolerance, so a row they alone
  // act on keeps a residual of roundoff size: that is a zero, not an equation to violate.
  std::vector<double> magnitude(size_t(region_rows), 0.0);
  for (int r = 0; r < region_rows; ++r) magnitude[size_t(r)] = std::abs(out.rhs[size_t(r)]);
  for (int j : fixed)
    for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k) {
      const int r = region_row[size_t(sys.row_index[size_t(k)])];
      if (r < 0) continue;
      out.rhs[size_t(r)] -= sys.value[size_t(k)] * force[size_t(j)];
      magnitude[size_t(r)] += std::abs(sys.value[size_t(k)] * force[size_t(j)]);
    }
  std::vector<char> has_variable(size_t(region_rows), 0);
  for (int j : columns)
    for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k)
      if (const int r = region_row[size_t(sys.row_index[size_t(k)])]; r >= 0)
        has_variable[size_t(r)] = 1;
  for (int r = 0; r < region_rows; ++r)
    if (!has_variable[size_t(r)] && std::abs(out.rhs[size_t(r)]) <= 1e-6 * magnitude[size_t(r)])
      out.rhs[size_t(r)] = 0;
  for (int j : columns) {
    for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k) {
      const int r = region_row[size_t(sys.row_index[size_t(k)])];
      if (r < 0) continue;
      out.row_index.push_back(r);
      out.value.push_back(sys.value[size_t(k)]);
    }
    out.kind.push_back(sys.kind[size_t(j)]);
    out.contact.push_back(sys.contact[size_t(j)]);
    out.column_start.push_back(int(out.row_index.size()));
    if (sys.kind[size_t(j)] == ForceKind::Friction) out.friction_columns = out.columns();
  }
  return out;
}

// The bricks of `after` whose forces may differ from `before`'s: those not matched by place and
// shape (and, through the columns of `before`, the neighbours of bricks that are gone), and
// `ring` + 1 layers of neighbours around them.
struct Region {
  std::vector<int> match;  // per brick of `after`: the same brick in `before`, or -1
  std::vector<int> depth;  // per brick: its layer in the region (0: changed), or -1 outside
  std::vector<int> row;    // per row of `after`'s system: its row in the region's, or -1
  int rows = 0, bricks = 0, changed = 0;
};

// `touched`, `touched_before`: the bricks of each column of `after`'s and `before`'s systems.
Region grow_region(const Assembly& before, const std::vector<std::vector<int>>& touched_before,
                   const Assembly& after, const EquilibriumSystem& sys,
                   const std::vector<std::vector<int>>& touched, int ring) {
  const int n_after = int(after.bricks.size()), n_before = int(before.bricks.size());
  Region region;
  std::map<BrickKey, int> by_key;
  for (int i = 0; i < n_before; ++i) by_key[key_of(before.bricks[size_t(i)])] = i;
  region.match.assign(size_t(n_after), -1);
  std::vector<int> matched_by(size_t(n_before), -1);
  for (int i = 0; i < n_after; ++i)
    if (auto it = by_key.find(key_of(after.bricks[size_t(i)])); it != by_key.end()) {
      region.match[size_t(i)] = it->second;
      matched_by[size_t(it->second)] = i;
    }
  std::vector<std::vector<int>> columns_of(static_cast<size_t>(n_after));
  for (int j = 0; j < sys.columns(); ++j)
    for (int b : touched[size_t(j)]) columns_of[size_t(b)].push_back(j);
  std::vector<int>& depth = region.depth;
  depth.assign(size_t(n_after), -1);
  std::vector<int> frontier;
  auto seed = [&](int b) {
    if (b >= 0 && depth[size_t(b)] < 0) depth[size_t(b)] = 0, frontier.push_back(b);
  };
  for (int i = 0; i < n_after; ++i)
    if (region.match[size_t(i)] < 0) seed(i), ++region.changed;
  for (const auto& bricks : touched_before)
    if (std::any_of(bricks.begin(), bricks.end(), [&](int b) { return matched_by[size_t(b)] < 0; }))
      for (int b : bricks) seed(matched_by[size_t(b)]);
  for (int level = 1; level <= 1 + ring && !frontier.empty(); ++level) {
    std::vector<int> next;
    for (int b : frontier)
      for (int j : columns_of[size_t(b)])
        for (int other : touched[size_t(j)])
          if (depth[size_t(other)] < 0) depth[size_t(other)] = level, next.push_back(other);
    frontier = std::move(next);
  }
  region.row.assign(size_t(sys.rows), -1);
  for (int b = 0; b < n_after; ++b)
    if (depth[size_t(b)] >= 0) {
      ++region.bricks;
      for (int e = 0; e < EquilibriumSystem::kEquations; ++e)
        region.row[size_t(EquilibriumSystem::row(b, e))] = region.rows++;
    }
  return region;
}

// `after`'s columns by where they act: only on the region's bricks, across its boundary, or only
// outside it; those touching the outside with their column in `before` (`previous`).
struct RegionColumns {
  std::vector<int> previous;  // per column: the same column in `before`, or -1 (region only)
  std::vector<int> region_only, boundary, outside;
};

// nullopt unless every brick outside the region has the same forces on it as before: the same
// columns (mapped by key, with equal coefficients) and the same loads.
std::optional<RegionColumns> columns_around(int n_before, const EquilibriumSystem& was,
                                            const std::vector<std::vector<int>>& touched_before,
                                            const StabilityResult& before_result,
                                            const EquilibriumSystem& sys, const ContactGraph& graph,
                                            const std::vector<std::vector<int>>& touched,
                                            const Region& region) {
  const int n_after = int(region.match.size());
  std::vector<int> identity(static_cast<size_t>(n_before));
  for (int i = 0; i < n_before; ++i) identity[size_t(i)] = i;
  const ColumnKeys keys_before(was, before_result.graph, identity);
  std::map<ColumnKey, int> column_before;
  for (int j = 0; j < was.columns(); ++j) column_before[keys_before[j]] = j;
  const ColumnKeys keys(sys, graph, region.match);
  RegionColumns out;
  out.previous.assign(size_t(sys.columns()), -1);
  std::vector<int> columns_after(size_t(n_after), 0);
  for (int j = 0; j < sys.columns(); ++j) {
    bool in = false, out_side = false;
    for (int b : touched[size_t(j)]) (region.depth[size_t(b)] >= 0 ? in : out_side) = true;
    if (!out_side) {
      out.region_only.push_back(j);
      continue;
    }
    auto it = keys.valid(j) ? column_before.find(keys[j]) : column_before.end();
    if (it == column_before.end()) return std::nullopt;
    const int jb = it->second;
    const int length = sys.column_start[size_t(j) + 1] - sys.column_start[size_t(j)];
    if (length != was.column_start[size_t(jb) + 1] - was.column_start[size_t(jb)])
      return std::nullopt;
    for (int k = 0; k < length; ++k)
      if (std::abs(sys.value[size_t(sys.column_start[size_t(j)] + k)] -
                   was.value[size_t(was.column_start[size_t(jb)] + k)]) > 1e-9)
        return std::nullopt;
    out.previous[size_t(j)] = jb;
    (in ? out.boundary : out.outside).push_back(j);
    for (int b : touched[size_t(j)]) ++columns_after[size_t(b)];
  }
  std::vector<int> columns_before(size_t(n_before), 0);
  for (const auto& bricks : touched_before)
    for (int b : bricks) ++columns_before[size_t(b)];
  for (int b = 0; b < n_after; ++b) {
    if (region.depth[size_t(b)] >= 0) continue;
    const int bb = region.match[size_t(b)];
    if (columns_after[size_t(b)] != columns_before[size_t(bb)]) return std::nullopt;
    for (int e = 0; e < EquilibriumSystem::kEquations; ++e) {
      const double now = sys.rhs[size_t(EquilibriumSystem::row(b, e))],
                   then = was.rhs[size_t(EquilibriumSystem::row(bb, e))];
      if (std::abs(now - then) > 1e-9 * (1 + std::abs(then))) return std::nullopt;
    }
  }
  return out;
}

// The lower bound: the region's forces re-solved, the boundary's fixed at their analysed values
// (`force`).
double lower_bound(const EquilibriumSystem& sys, const Region& region, const RegionColumns& c,
                   const std::vector<double>& force, const StabilityOptions& stability) {
  double fixed_friction = 0;
  for (const auto* set : {&c.boundary, &c.outside})
    for (int j : *set)
      if (sys.kind[size_t(j)] == ForceKind::Friction)
        fixed_friction = std::max(fixed_friction, force[size_t(j)]);
  const EquilibriumSystem local =
      region_system(sys, region.row, region.rows, c.region_only, c.boundary, force);
  std::string message;
  const LpSolution s =
      solve_supports_boxed([&](double bound) { return scaled_lp(local, bound); }, stability,
                           message, nullptr, false, scale_objective_options());
  if (s.outcome != LpOutcome::Optimal) return -kInfinity;
  const double w = s.x.back();
  // Below w = 1e-3 (friction over 1000 T) the solve cannot tell "little" from "none".
  if (w < 1e-3) return -kInfinity;
  const double region_friction = w >= kMaxScale * (1 - 1e-6) ? 0.0 : kMaxFrictionLoad / w;
  return kMaxFrictionLoad - std::max(region_friction, fixed_friction);
}

// The upper bound. The scaled LP is max w s.t. A·x = 0 (w's column is −b/T), x in its box. For
// duals y (Clp's sign, so the max form's are −y), w* ≤ Σ_j max over x_j's box of (c_j + a_jᵀy)·x_j
// wherever that is finite; with y fixed outside the region this is the region's LP with every
// column touching the region priced by the outside duals, plus the fixed part of the columns
// outside it.
double upper_bound(const EquilibriumSystem& sys, const Region& region, const RegionColumns& c,
                   const std::vector<double>& force, const StabilityResult& before_result,
                   const StabilityOptions& stability) {
  std::vector<double> y_outside(size_t(sys.rows), 0.0);
  for (int b = 0; b < int(region.match.size()); ++b)
    if (region.depth[size_t(b)] < 0)
      for (int e = 0; e < EquilibriumSystem::kEquations; ++e)
        y_outside[size_t(EquilibriumSystem::row(b, e))] =
            before_result.row_duals[size_t(EquilibriumSystem::row(region.match[size_t(b)], e))];
  auto priced = [&](int j) {  // a_jᵀy over the rows outside the region
    double sum = 0;
    for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k)
      sum += sys.value[size_t(k)] * y_outside[size_t(sys.row_index[size_t(k)])];
    return sum;
  };
  double constant =
      0;  // friction in [0, 1]; normal and support columns contribute 0 at a dual optimum
  for (int j : c.outside)
    if (sys.kind[size_t(j)] == ForceKind::Friction) constant += std::max(0.0, priced(j));
  std::vector<int> columns = c.region_only;
  columns.insert(columns.end(), c.boundary.begin(), c.boundary.end());
  std::sort(columns.begin(), columns.end());  // friction columns first, as everywhere
  std::vector<double> cost;                   // minimized: −(c_j + a_jᵀy)
  for (int j : columns) cost.push_back(-priced(j));
  double w_gain = 1;  // c_w + (w's column)ᵀy over the outside rows
  for (int r = 0; r < sys.rows; ++r)
    if (region.row[size_t(r)] < 0)
      w_gain -= sys.rhs[size_t(r)] / kMaxFrictionLoad * y_outside[size_t(r)];
  const EquilibriumSystem local = region_system(sys, region.row, region.rows, columns, {}, force);
  std::string message;
  const LpSolution s = solve_supports_boxed(
      [&](double bound) {
        LpData lp = scaled_lp(local, bound);
        std::copy(cost.begin(), cost.end(), lp.objective.begin());
        lp.objective.back() = -w_gain;
        return lp;
      },
      stability, message, nullptr, false);
  if (s.outcome != LpOutcome::Optimal || s.x.back() >= kMaxScale * (1 - 1e-6)) return kInfinity;
  const double w_upper = -s.objective + constant;
  return w_upper <= 0 ? -kInfinity : kMaxFrictionLoad * (1 - 1 / std::min(w_upper, kMaxScale));
}

}  // namespace

CmBounds bound_cm_locally(const Assembly& before, const StabilityResult& before_result,
                          const Assembly& after, const LocalBoundOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CmBounds out;
  auto finish = [&]() -> CmBounds {
    out.seconds = seconds_since(start);
    return out;
  };
  for (const Assembly* a : {&before, &after}) {
    if (!a->carried.empty()) return finish();
    for (const Brick& b : a->bricks)
      if (b.pose || b.fixed) return finish();  // bricks are matched by their lattice cells
  }
  const EquilibriumSystem was =
      build_equilibrium(before, before_result.graph, before_result.connectivity);
  if (before_result.status != StabilityStatus::Solved || !one_body_per_brick(was) ||
      before_result.forces.size() != size_t(was.columns()) ||
      before_result.row_duals.size() != size_t(was.rows))
    return finish();
  const ContactGraph graph = ContactGraph::build(after, options.stability.ground);
  const Connectivity connectivity = analyze_connectivity(int(after.bricks.size()), graph);
  if (!connectivity.all_grounded()) return finish();
  const EquilibriumSystem sys = build_equilibrium(after, graph, connectivity);
  if (!one_body_per_brick(sys)) return finish();

  const auto touched = bricks_of_columns(sys), touched_before = bricks_of_columns(was);
  const Region region = grow_region(before, touched_before, after, sys, touched, options.ring);
  out.changed_bricks = region.changed;
  out.region_bricks = region.bricks;
  if (out.region_bricks > options.max_region_share * double(after.bricks.size())) return finish();
  const auto columns = columns_around(int(before.bricks.size()), was, touched_before, before_result,
                                      sys, graph, touched, region);
  if (!columns) return finish();
  out.valid = true;
  if (out.region_bricks == 0) {  // the same bricks in the same places, with the same loads
    out.lower = out.upper = before_result.cm;
    return finish();
  }
  std::vector<double> force(size_t(sys.columns()), 0.0);
  for (int j = 0; j < sys.columns(); ++j)
    if (const int jb = columns->previous[size_t(j)]; jb >= 0)
      force[size_t(j)] = before_result.forces[size_t(jb)];
  if (options.lower) out.lower = lower_bound(sys, region, *columns, force, options.stability);
  if (options.upper)
    out.upper = upper_bound(sys, region, *columns, force, before_result, options.stability);
  return finish();
}

}  // namespace lego::physics
