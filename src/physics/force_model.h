#pragma once
#include <cstdint>
#include <vector>

#include "core/assembly.h"
#include "physics/connectivity.h"
#include "physics/contact_graph.h"

namespace lego::physics {

// Constants of PHYSICS.md. Forces inside the solver are in g·m/s² (1 g·m/s² = 1 mN).
inline constexpr double kGravity = 9.8;
inline constexpr double kMaxFrictionLoad = 71.658 * kGravity;  // T, per contact point
// The heaviest external weight (grams) the tools take (--load, --load-top): a tonne, far past
// what any LEGO model carries. C_M stays linear in the load to 1e7 g; at 1e9 g the model's own
// weight is lost in the solver's rounding and it finds no equilibrium, and at 1e110 Clp aborts.
inline constexpr double kMaxLoadGrams = 1e6;
// A joint carries whole parts of a model: its columns count in units of this many times a
// contact's, so that they stay inside the box the solver puts around free columns (a joint
// holding 10 N reached 527 of the box's 1,000 on the corpus's shopping centre, and the box was
// widened and the LP solved again).
inline constexpr double kJointUnit = 100;
// The moment a friction pin holds about its axis before it turns (g·m/s²·stud): an estimate, not
// a measurement (docs/physics.md, "Joints"): a light Technic beam's weight a few studs out.
inline constexpr double kFrictionPinMoment = 5 * kGravity;

enum class ForceKind : uint8_t { Friction, Normal, Support };

// The equilibrium equations of PHYSICS.md, A·x = b: six rows per brick (force x, y, z, torque
// x, y, z about the brick's centre), one column per contact force; an assumed-rigid joint is six
// free columns (a force and a moment passed between its two bricks). Fixed bricks, the ground and
// floating bricks have no rows. Friction columns come first, in the order of
// ContactGraph::friction_points, so column i is friction point i of the contacts taken. Stored
// column-major, built in one pass, so solvers can take the arrays as they are.
struct EquilibriumSystem {
  int rows = 0;
  std::vector<int> column_start{0};  // size columns + 1
  std::vector<int> row_index;
  std::vector<double> value;
  std::vector<ForceKind> kind;  // per column
  std::vector<int> contact;     // per column: index into ContactGraph::contacts
  std::vector<double> rhs;      // b, per row
  // Per brick of the assembly: its body (block of rows), -1 when it has none. Empty in a block of
  // the system (equilibrium_blocks.h): a town's hundreds of blocks would each hold a map as long
  // as the town.
  std::vector<int> body_of;
  std::vector<int> brick_of_body;  // per body: its brick (ascending)

  int columns() const { return int(kind.size()); }
  // b − A·forces: what the forces (per column) leave unbalanced, per row.
  std::vector<double> unbalanced(const std::vector<double>& forces) const;
  int friction_columns = 0;
  // With Formulation::turning_joints_hold: the column of the moment each turning joint holds
  // about its axis (its contact is `contact[column]`).
  std::vector<int> turning_columns;
  static constexpr int kEquations = 6;  // rows per body
  static int row(int body, int equation) { return kEquations * body + equation; }
  static int body_of_row(int row) { return row / kEquations; }
};

// The choices of the force model that the physical evidence decides between (docs/physics.md,
// "Against the evidence"). The defaults are the model both tools use; the others are there to be
// measured against it (tools/bench, section "physics").
struct Formulation {
  // How hard each contact of a knob grips: as the knob's balance lets it (knob_grip.h), or every
  // contact at T, as in the paper.
  bool knob_balance = true;
  // Where two snapped parts push on each other: at the corners of the patch where their faces
  // meet (the paper), or only at the contact points of the knobs (StableLego, BrickSim).
  bool push_at_knobs = false;
  // Two knobs or more hold a twist about their axis (a free moment, as the support force is a
  // free force); false: one support force at the patch's centre, as the paper (2D) writes it.
  bool knobs_hold_twist = true;
  // Joints that turn (a pin in a hole) hold a moment about their axis as well, as if welded:
  // what the model would be if they did not turn (the diagnosis of a model that stands only so).
  bool turning_joints_hold = false;
};

// Lengths in the equations are in studs (a plate is 0.4 stud): torques need true proportions.
// Contacts with a floating brick are left out, and so are floating bricks' rows.
EquilibriumSystem build_equilibrium(const Assembly& assembly, const ContactGraph& graph,
                                    const Connectivity& connectivity,
                                    const Formulation& formulation = {});

}  // namespace lego::physics
