#pragma once
// The scaled form of the stability LP (docs/stability-lp.md) and how it is solved: support forces
// boxed while the interior point method runs, the box widened when the answer touches it, Clp's
// dual simplex when the interior point method fails. Shared by the whole-model analysis
// (stability.cpp) and the local bounds of refinement (local_bounds.cpp).
#include <functional>
#include <string>

#include "physics/clp_lp.h"
#include "physics/force_model.h"
#include "physics/interior_point.h"
#include "physics/stability.h"

namespace lego::physics {

// In the scaled form w = T / max f. Past this bound friction is negligible: C_M = T.
inline constexpr double kMaxScale = 1e6;
// The whole-model analysis first caps w here (C_M within a thousandth of T), and only a model that
// reaches it is solved again up to kMaxScale, with the support box as wide as the cap.
inline constexpr double kFirstScale = 1e3;

// LpStats::solver where our interior point method failed and Clp's dual simplex took over.
inline constexpr const char* kClpAfterOurs = "Clp dual simplex after the interior point method";

// The equilibrium columns with the bounds of their kind: friction in [0, friction_upper], normal
// forces ≥ 0, support forces in ±support_bound (free when infinite); rows A·x = rhs_scale·b.
LpData equilibrium_lp(const EquilibriumSystem& sys, double friction_upper, double rhs_scale,
                      double support_bound);

// max w s.t. A·ξ − (b/T)·w = 0, 0 ≤ ξ_friction ≤ 1, 0 ≤ w ≤ cap (minimizes −w). Column
// sys.columns() is w, the one dense column.
LpData scaled_lp(const EquilibriumSystem& sys, double support_bound, double cap = kMaxScale);

// max v s.t. A·ξ − (b/T)·v = 0 over the normal and support columns only, 0 ≤ v ≤ 1: v = 1 when
// the model stands without friction. Column sys.columns() − sys.friction_columns is v.
LpData frictionless_lp(const EquilibriumSystem& sys, double support_bound);

// Our interior point method on an LP whose lower bounds are all finite; Failed when it does not
// converge.
LpSolution solve_interior(const LpData& lp, const IpmOptions& options = {});

const char* method_name(LpMethod method);  // "interior point", "Clp dual simplex", ...

// Options of our interior point method for an LP whose objective is −w, w the scale of the
// scaled form: the duality gap is judged by what it does to C_M = T·(1 − 1/w).
IpmOptions scale_objective_options();

// Solves the LP that `make(bound)` builds with its support columns boxed at ±bound (those whose
// bounds are exactly ±bound), by options.method: interior methods start at
// options.support_bound and widen the box tenfold while the answer touches it, so the answer is
// that of the free problem; our interior point method hands over to Clp's dual simplex when it
// fails (unless `simplex_fallback` is false, or `failure_explained` says true when asked: then
// the failure is the answer), and `message` says so. Row duals follow Clp's sign: reduced cost =
// c − Aᵀy. `ipm` goes to our interior point method.
LpSolution solve_supports_boxed(const std::function<LpData(double bound)>& make,
                                const StabilityOptions& options, std::string& message,
                                LpStats* stats = nullptr, bool simplex_fallback = true,
                                const IpmOptions& ipm = {},
                                const std::function<bool()>& failure_explained = {});

}  // namespace lego::physics
