#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "core/assembly.h"
#include "physics/connectivity.h"
#include "physics/contact_graph.h"
#include "physics/force_model.h"

namespace lego::physics {

class SolvedBlocks;

enum class StabilityStatus {
  Solved,            // C_M is a number (stable when > 0)
  Empty,             // no bricks (or only the ground's own)
  Floating,          // nothing but the ground stands: every brick floats, no LP
  NoEquilibrium,     // connected, but no forces balance it (C_M = -inf)
  IterationLimit,    // the solver stopped on its iteration or time limit
  NumericalTrouble,  // the solver failed; no number is given
};
const char* to_string(StabilityStatus status);
// Whether the analysis reached a verdict: false when the solver gave up (iteration limit or
// numerical trouble). Both tools call that state UNDECIDED (exit 4).
bool decided(StabilityStatus status);

// How the LP of PHYSICS.md is posed to Clp (docs/stability-lp.md has the measurements).
enum class LpForm {
  // max w s.t. A·ξ − (b/T)·w = 0, 0 ≤ ξ_friction ≤ 1; then C_M = T·(1 − 1/w*). Six rows per
  // brick; equivalent to MaxMin (scale the forces by w = T/max f).
  Scaled,
  // max t s.t. t + f_i ≤ T for every friction point, A·x = b: the LP as PHYSICS.md writes it.
  MaxMin,
};
// InteriorPoint is our own (interior_point.h); the others are Clp's.
enum class LpMethod { InteriorPoint, DualSimplex, PrimalSimplex, Barrier, BarrierNoCrossover };

struct StabilityOptions {
  GroundMode ground = GroundMode::Baseplate;
  LpForm form = LpForm::Scaled;
  LpMethod method = LpMethod::InteriorPoint;
  bool presolve = true;
  bool scaling = true;
  bool brick_capacity = false;  // also compute the per-brick capacity (a QP; for heat maps)
  // Scaled form with an interior point method: |support force| ≤ this (in units of the largest
  // friction force) while solving; raised and solved again when the solution touches it.
  double support_bound = 1e3;
  double max_seconds = 3600;
  // The run's budget (brickcheck's --max-seconds for a file), which every stage checks: the
  // contact graph and the solves stop with OutOfTime when it is spent.
  const Budget* budget = nullptr;
  // The scaled LP's one scale column couples every row: structures that no force joins (a
  // town's buildings) are solved apart, gathered into LPs of at least this many bodies
  // (equilibrium_blocks.h). C_M is the same; only the time differs.
  int block_bodies = 50;
  // Blocks solved at once, on as many threads with one BLAS thread each, where two or more are
  // large (a town): 1 where analyses already run side by side.
  int block_jobs = 1;
  // Blocks solved by earlier analyses with these options, reused where their equations are the
  // same and kept for later ones (solved_blocks.h); none: every block is solved.
  SolvedBlocks* solved_blocks = nullptr;
  // The force model's choices; the default is the model (force_model.h).
  Formulation formulation = {};
  // Carried parts and parts of two lattices that touch tie what they touch rigidly; false: they
  // tie nothing (ContactGraph::build), as brickcheck --strict checks a verdict without them.
  bool assumed_joints = true;
  // With no equilibrium, name the joints that turn and must not (turning_joints): a second LP
  // as large as the first, so a caller that analyses again (report/audit.cpp) asks once, last.
  bool diagnose_turning = true;
};

// The seconds a solve may take: `seconds`, within what is left of the options' budget.
inline double solve_seconds(const StabilityOptions& o, double seconds) {
  return o.budget ? std::min(seconds, o.budget->seconds_left()) : seconds;
}

// A pair of bricks whose friction points bind at the optimum, with its share of the duals.
struct WeakContact {
  int contact = 0;  // index into ContactGraph::contacts
  int lower = kGround, upper = 0;
  double share = 0;  // of the sum of all binding duals, 0..1
};

// LpStats::capacity_solver when the per-brick capacity shows the analysis's own forces: one
// distribution that reaches C_M, not the least-norm one.
inline constexpr const char* kCapacityFromAnalysis = "the analysis's forces";

struct LpStats {
  int rows = 0, columns = 0, nonzeros = 0;
  int iterations = 0;
  // Which solver gave the answer: "interior point", "Clp dual simplex", or "Clp dual simplex
  // after the interior point method" when ours failed and Clp took over (`message` says why).
  std::string solver;
  // What gave the per-brick capacity (heat maps): "interior point", "Clp QP" (when the analysis is
  // asked of Clp), or kCapacityFromAnalysis when our method failed (`message` says why).
  std::string capacity_solver;
  int capacity_iterations = 0;  // of our interior point method on the capacity QP, all boxes
  double graph_seconds = 0, build_seconds = 0, solve_seconds = 0, capacity_seconds = 0;
};

// One LP of a model whose independent structures are solved apart (equilibrium_blocks.h): a
// structure of many parts (a town's building), or small ones gathered.
struct BlockOutcome {
  std::vector<int> bricks;  // sorted
  int structures = 1;
  StabilityStatus status = StabilityStatus::Empty;
  double cm = 0;  // g·m/s², when Solved
  double cm_gf() const { return cm / kGravity; }
};

struct StabilityResult {
  StabilityStatus status = StabilityStatus::Empty;
  double cm = 0;                       // C_M in g·m/s² (valid when Solved)
  std::vector<WeakContact> weakest;    // ranked by share, largest first
  std::vector<double> brick_capacity;  // per brick, g·m/s² (when asked for and Solved)
  // With NoEquilibrium: the bricks whose rigid bodies no forces can hold (they tip or hang).
  std::vector<int> unbalanced;
  // With NoEquilibrium: the joints that turn (ContactGraph::contacts) and must not for the model
  // to stand, with the least moment each would have to hold about its axis (g·m/s²·stud).
  std::vector<std::pair<int, double>> turning;
  ContactGraph graph;
  Connectivity connectivity;
  LpStats stats;
  std::string message;  // the solver's words when it did not solve
  // The optimum of the scaled form (Solved, C_M < T): every force, in g·m/s², per column of
  // build_equilibrium(assembly, graph), and the LP's row duals (Clp's sign: reduced cost =
  // c − Aᵀy, with c = −1 on w). What local_bounds.h starts from; empty otherwise.
  std::vector<double> forces, row_duals;
  // Where the structures were solved apart: each LP's outcome, weakest first (no equilibrium,
  // then any the solver could not decide, then by C_M); empty when one LP held the model.
  std::vector<BlockOutcome> blocks;
  // C_M is a lower bound proven by a force field (step_stability.h), not the LP's optimum; the
  // weakest contacts, turning joints and capacities are then not computed.
  bool certified = false;

  double cm_newton() const { return cm / 1000.0; }
  double cm_gf() const { return cm / kGravity; }
  // Floating parts are left out of the LP (PHYSICS.md): C_M is that of what stands, and a model
  // with floating parts is not stable whatever it is.
  bool stable(double min_cm_gf = 0) const {
    return status == StabilityStatus::Solved && cm_gf() > min_cm_gf && connectivity.all_grounded();
  }
};

// The paper's force-based analysis (section 6, PHYSICS.md): connectivity first, then the LP over
// everything that reaches the ground.
StabilityResult analyze_stability(const Assembly& assembly, const StabilityOptions& options = {});
// analyze_stability in three parts, for callers that look at the system before solving it
// (step_stability.h): the contact graph, connectivity and ground; the equilibrium system (the
// status is Empty or Floating when it has no rows); the LP and what follows from it.
StabilityResult analyze_contacts(const Assembly& assembly, const StabilityOptions& options);
EquilibriumSystem build_equilibrium(const Assembly& assembly, StabilityResult& result,
                                    const StabilityOptions& options);
void solve_equilibrium(const Assembly& assembly, const EquilibriumSystem& system,
                       const StabilityOptions& options, StabilityResult& result);
// With no equilibrium, the joints that turn and must not, each with the least moment about its
// axis it would have to hold (gf·stud · g): none in a structure that does not stand even with
// joints that hold.
std::vector<std::pair<int, double>> turning_joints(const Assembly& assembly,
                                                   const StabilityResult& result,
                                                   const StabilityOptions& options);

}  // namespace lego::physics
