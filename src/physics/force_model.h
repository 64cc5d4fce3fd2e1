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
  std::vector<int> body_of;     // per brick: its block of rows, -1 when it has none

  int columns() const { return int(kind.size()); }
  int friction_columns = 0;
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
};

// Lengths in the equations are in studs (a plate is 0.4 stud): torques need true proportions.
// Contacts with a floating brick are left out, and so are floating bricks' rows.
EquilibriumSystem build_equilibrium(const Assembly& assembly, const ContactGraph& graph,
                                    const Connectivity& connectivity,
                                    const Formulation& formulation = {});

}  // namespace lego::physics
