#include "physics/step_stability.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/stopwatch.h"
#include "physics/certificate.h"

namespace lego::physics {
namespace {

// Column j's key: the whole model's upper and lower bricks, and its place among their columns.
std::vector<uint64_t> column_keys(const EquilibriumSystem& sys, const ContactGraph& graph,
                                  const std::vector<int>& whole_index) {
  std::vector<uint64_t> keys(static_cast<size_t>(sys.columns()));
  std::unordered_map<uint64_t, uint64_t> seen;  // per pair of bricks: columns so far
  for (int j = 0; j < sys.columns(); ++j) {
    const Contact& c = graph.contacts[size_t(sys.contact[size_t(j)])];
    const uint64_t upper = uint64_t(whole_index[size_t(c.upper)]) + 1;
    const uint64_t lower = c.lower == kGround ? 0 : uint64_t(whole_index[size_t(c.lower)]) + 1;
    const uint64_t pair = upper << 40 | lower << 16;
    keys[size_t(j)] = pair | (seen[pair]++ & 0xffff);
  }
  return keys;
}

StepForces keyed(const std::vector<uint64_t>& keys, const std::vector<double>& forces,
                 std::shared_ptr<const LoadSpread> spread) {
  StepForces out;
  out.by_column.reserve(forces.size());
  for (size_t j = 0; j < forces.size() && j < keys.size(); ++j)
    if (forces[j] != 0) out.by_column.emplace(keys[j], forces[j]);
  out.spread = std::move(spread);
  return out;
}

// The bricks of the whole model that the system's bodies are.
std::vector<int> body_bricks(const EquilibriumSystem& sys, const std::vector<int>& whole_index) {
  std::vector<int> out;
  out.reserve(sys.brick_of_body.size());
  for (int brick : sys.brick_of_body) out.push_back(whole_index[size_t(brick)]);
  return out;
}

// The LP's part of a step's analysis, into out.result (which holds the contacts already).
void solve(const Assembly& partial, const StepSystem& prepared, const StabilityOptions& options,
           bool with_spread, StepStability& out) {
  StabilityResult& r = out.result;
  const EquilibriumSystem& sys = prepared.system;
  solve_equilibrium(partial, sys, options, r);
  if (r.status != StabilityStatus::Solved) return;
  std::shared_ptr<const LoadSpread> spread;
  if (with_spread && !r.forces.empty())
    spread = std::make_shared<const LoadSpread>(sys, prepared.column_keys, prepared.body_bricks,
                                                r.row_duals, r.cm);
  out.forces = keyed(prepared.column_keys, r.forces, std::move(spread));
}

}  // namespace

bool solve_weakest_again(const std::vector<StepMargin>& steps, int solved) {
  if (solved == 0) return true;
  if (solved >= kWeakestStepSolves) return false;
  double exact = std::numeric_limits<double>::infinity();
  for (const StepMargin& s : steps)
    if (!s.certified) exact = std::min(exact, s.cm_gf);
  const auto below = std::count_if(steps.begin(), steps.end(), [&](const StepMargin& s) {
    return s.certified && s.cm_gf < exact;
  });
  return below <= kWeakestStepSolves;
}

StepSystem prepare_step(const Assembly& partial, const std::vector<int>& whole_index,
                        const StabilityOptions& options, const ContactGraph* model_contacts) {
  StepSystem out;
  if (model_contacts) {  // analyze_contacts' part, the graph taken from the model's
    const auto begin = std::chrono::steady_clock::now();
    out.contacts.graph = model_contacts->among(whole_index);
    out.contacts.connectivity =
        analyze_connectivity(int(partial.bricks.size()), out.contacts.graph);
    out.contacts.stats.graph_seconds = seconds_since(begin);
  } else {
    out.contacts = analyze_contacts(partial, options);
  }
  if (partial.bricks.empty()) return out;
  out.system = build_equilibrium(partial, out.contacts, options);
  if (out.system.rows == 0) return out;
  out.column_keys = column_keys(out.system, out.contacts.graph, whole_index);
  out.body_bricks = body_bricks(out.system, whole_index);
  return out;
}

bool steps_take_contacts_from(const ContactGraph& graph) {
  // On a tilted table the ground's studs and baseplates are found from the parts' lowest point.
  return graph.pairwise() && graph.ground_slope == std::array<double, 2>{0, 0};
}

std::optional<ContactGraph> steps_contacts(const Assembly& model, const StabilityOptions& options) {
  // Without a given ground, each step's is found from its own parts (or the table it settles on).
  if (!model.ground_height || !model.carried.empty()) return std::nullopt;
  ContactGraph graph =
      ContactGraph::build(model, options.ground, options.assumed_joints, options.budget);
  if (!steps_take_contacts_from(graph)) return std::nullopt;
  return graph;
}

StepStability analyze_step(const Assembly& partial, const std::vector<int>& whole_index,
                           const StepForces& start, const StabilityOptions& options,
                           std::optional<double> certify_above_gf) {
  return analyze_step(partial, prepare_step(partial, whole_index, options), start, options,
                      certify_above_gf);
}

StepStability analyze_step(const Assembly& partial, StepSystem prepared, const StepForces& start,
                           const StabilityOptions& options,
                           std::optional<double> certify_above_gf) {
  StepStability out;
  StabilityResult& r = out.result;
  r = std::move(prepared.contacts);
  if (partial.bricks.empty() || prepared.system.rows == 0) return out;
  const EquilibriumSystem& sys = prepared.system;
  const std::vector<uint64_t>& keys = prepared.column_keys;
  if (certify_above_gf) {
    const auto begin = std::chrono::steady_clock::now();
    std::vector<double> from(keys.size(), 0.0);
    for (size_t j = 0; j < keys.size(); ++j)
      if (auto it = start.by_column.find(keys[j]); it != start.by_column.end())
        from[j] = it->second;
    // A certificate whose bound is below this share of what the LP last gave (or of T, before
    // any LP) is not taken: the LP costs little more than the certificates after it would (each
    // begins from the forces of the one before, so a loose bound stays loose), it brings a new
    // spread, and the weakest step's exact C_M is asked of the LP anyway. The duck at height 30
    // (docs/performance.md, 2026-12-07): taking every certificate, 13.5 s and "at least 0.44 gf";
    // half, 18.4 s and "at least 39.8 gf"; body by body alone, 29.6 s and "at least 0.75 gf".
    const double floor = kKeptShare * (start.spread ? start.spread->solved_cm() : kMaxFrictionLoad);
    // A spread's certificate under it lowers its largest frictions first (certificate.h): on the
    // duck at height 40, brickcheck --steps 33.7 s -> 29.0 s. Not body by body: there, before any
    // LP, each step began lowering where the one before left off (110 steps at 0.12 s each on the
    // same duck), where one LP early on, on a small model, brings a spread.
    const double wanted = std::max(floor, *certify_above_gf * kGravity) * (1 + 1e-9);
    auto certified = [&](const Certificate& c, const char* how) {
      r.stats.solve_seconds = seconds_since(begin);
      if (!c.found || c.cm < floor || c.cm / kGravity <= *certify_above_gf) return false;
      r.status = StabilityStatus::Solved;
      r.cm = c.cm;
      r.certified = true;
      r.stats.solver = how;
      out.forces = keyed(keys, c.forces, start.spread);
      return true;
    };
    // The spread of the latest step the LP solved, where there is one; else body by body (the
    // first steps, which stand without friction: the LP there has no forces to spread).
    if (const LoadSpread* spread = start.spread.get(); spread && spread->usable()) {
      std::vector<int> spread_body_of;
      Spreading spreading;
      for (int whole : prepared.body_bricks) {
        spread_body_of.push_back(spread->body_of_brick(whole));
        spreading.bodies.push_back(spread_body_of.back() >= 0);
      }
      spreading.spread = [&](std::vector<double>& x) {
        return spread->spread(sys, keys, spread_body_of, x);
      };
      if (certified(certify(sys, r.graph, from, &spreading, wanted), kSpreadCertificate))
        return out;
    } else if (certified(certify(sys, r.graph, from), kBodyByBodyCertificate)) {
      return out;
    }
  }
  solve(partial, prepared, options, certify_above_gf.has_value(), out);
  return out;
}

StepStability solve_step(const Assembly& partial, StepSystem prepared,
                         const StabilityOptions& options, bool spread) {
  StepStability out;
  out.result = std::move(prepared.contacts);
  if (partial.bricks.empty() || prepared.system.rows == 0) return out;
  solve(partial, prepared, options, spread, out);
  return out;
}

}  // namespace lego::physics
