#include "physics/step_stability.h"

#include <chrono>

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

StepForces keyed(const std::vector<uint64_t>& keys, const std::vector<double>& forces) {
  StepForces out;
  out.reserve(forces.size());
  for (size_t j = 0; j < forces.size() && j < keys.size(); ++j)
    if (forces[j] != 0) out.emplace(keys[j], forces[j]);
  return out;
}

}  // namespace

StepStability analyze_step(const Assembly& partial, const std::vector<int>& whole_index,
                           const StepForces& start, const StabilityOptions& options,
                           std::optional<double> certify_above_gf) {
  StepStability out;
  StabilityResult& r = out.result;
  r = analyze_contacts(partial, options);
  if (partial.bricks.empty()) return out;
  const EquilibriumSystem sys = build_equilibrium(partial, r, options);
  if (sys.rows == 0) return out;
  const std::vector<uint64_t> keys = column_keys(sys, r.graph, whole_index);
  if (certify_above_gf) {
    const auto begin = std::chrono::steady_clock::now();
    std::vector<double> from(keys.size(), 0.0);
    for (size_t j = 0; j < keys.size(); ++j)
      if (auto it = start.find(keys[j]); it != start.end()) from[j] = it->second;
    const Certificate c = certify(sys, r.graph, from);
    r.stats.solve_seconds = seconds_since(begin);
    if (c.found && c.cm / kGravity > *certify_above_gf) {
      r.status = StabilityStatus::Solved;
      r.cm = c.cm;
      r.certified = true;
      r.stats.solver = "certificate";
      out.forces = keyed(keys, c.forces);
      return out;
    }
  }
  solve_equilibrium(partial, sys, options, r);
  if (r.status == StabilityStatus::Solved) out.forces = keyed(keys, r.forces);
  return out;
}

}  // namespace lego::physics
