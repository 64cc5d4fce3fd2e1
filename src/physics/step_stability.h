#pragma once
// A build step's stability at the cost of a few rows per brick: a certificate that it stands
// (certificate.h), begun from the forces of a step before, and the LP only where no certificate
// is found. What the report needs of a step is that it stands; the exact C_M is asked of the
// weakest step alone.
#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "physics/load_spread.h"
#include "physics/stability.h"

namespace lego::physics {

// Forces keyed by the bricks of the whole model they act between, so that a later step (a
// different system, the same bricks and more) can begin from them; and the spread of the latest
// step the LP solved, which moves loads on its bodies as the LP would (load_spread.h).
struct StepForces {
  std::unordered_map<uint64_t, double> by_column;
  std::shared_ptr<const LoadSpread> spread;
  bool empty() const { return by_column.empty(); }
};

struct StepStability {
  StabilityResult result;  // `certified` when a certificate decided it
  // Forces that balance the step, for a later step to begin from: the certificate's or the LP's.
  // A step that adds a few bricks to one the LP solved is certified from the LP's forces in most
  // cases (the bunny at height 40 in steps of 30 bricks: 97 of 140 steps, against 30 from the
  // certificates' forces alone), though the interior point method's forces carry supports that
  // balance each other.
  StepForces forces;
};

// StabilityResult::stats.solver of a step a certificate decided: body by body (certificate.h),
// or by the spread of a step the LP solved (load_spread.h).
inline constexpr const char* kBodyByBodyCertificate = "certificate";
inline constexpr const char* kSpreadCertificate = "certificate from the LP's spread";

// A step's certificate is taken when its bound is at least this share of the C_M the LP gave
// the step its spread comes from (of T where there is none): step_stability.cpp says why.
inline constexpr double kKeptShare = 0.5;

// The weakest step's C_M is reported exactly: while the smallest step C_M is a certificate's
// bound, that step is solved by the LP, at most this many times. Not until none is: bounds are
// often below the others' exact C_M, and solving them all undoes the certificates (Bunde nog
// Kanden's 45 certified steps of 48 fell to 11); not once: the bunny at height 20 then reported
// a smallest step C_M of at least 7.7 gf, the first of three loose bounds.
inline constexpr int kWeakestStepSolves = 3;

// A step's C_M as the report has it: exact, or a certificate's bound.
struct StepMargin {
  double cm_gf = 0;
  bool certified = false;
};
// Whether the LP should solve the weakest step once more, `solved` times already: the first
// time always (the smallest bound may be the weakest step's); after, while solves are left, only
// where a few bounds (kWeakestStepSolves or fewer) lie below the smallest exact C_M, which the
// solves left may settle (the crate sample's three did). Where dozens do, no few solves can: the
// smallest step C_M stays a bound however they are spent (legolize's duck at height 40: dozens
// of bounds at 35-40 gf, every step the LP solved at 67-71 gf).
bool solve_weakest_again(const std::vector<StepMargin>& steps, int solved);

// What a step's analysis needs before any forces: the contacts of the model after it, its
// equilibrium system and its columns' keys in the whole model. It owes nothing to the steps
// before, so the next step's is made while this one is decided (layout/build_order.cpp).
struct StepSystem {
  StabilityResult contacts;  // analyze_contacts and build_equilibrium's part of the result
  EquilibriumSystem system;
  std::vector<uint64_t> column_keys;
  std::vector<int> body_bricks;  // per body of the system, its brick in the whole model
};
// `model_contacts`: steps_contacts' for the whole model, or none (each step's contacts are then
// searched for in its model, about 20 ms a step at 4,000 bricks).
StepSystem prepare_step(const Assembly& partial, const std::vector<int>& whole_index,
                        const StabilityOptions& options,
                        const ContactGraph* model_contacts = nullptr);

// Whether the build steps' contacts can be taken from `graph`, the whole model's, for steps
// built on its ground (Assembly::ground_height its ground_height): what a search of a step's
// model finds where every contact owes nothing to a third part and the ground is level.
bool steps_take_contacts_from(const ContactGraph& graph);
// The contacts of a whole model whose steps take theirs from it, or none. `model`: every brick,
// as the steps' models have them (the same given ground, no carried parts).
std::optional<ContactGraph> steps_contacts(const Assembly& model, const StabilityOptions& options);

// The model after a step: `partial`, whose brick i is brick whole_index[i] of the whole model.
// With `certify_above_gf`, a certificate from `start` that C_M / g exceeds it is the answer;
// otherwise, and when none is found, the LP's. `prepared`: prepare_step's for the same model.
StepStability analyze_step(const Assembly& partial, StepSystem prepared, const StepForces& start,
                           const StabilityOptions& options, std::optional<double> certify_above_gf);
StepStability analyze_step(const Assembly& partial, const std::vector<int>& whole_index,
                           const StepForces& start, const StabilityOptions& options,
                           std::optional<double> certify_above_gf);

// The step solved by the LP alone, as analyze_step solves one no certificate decides: with
// `spread`, the forces it gives carry the LoadSpread the steps after it are certified from.
StepStability solve_step(const Assembly& partial, StepSystem prepared,
                         const StabilityOptions& options, bool spread);

}  // namespace lego::physics
