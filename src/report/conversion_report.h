#pragma once
// legolize's --report: what was converted, how it turned out, and where the time went
// (documented in docs/legolize-report.md).
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "physics/stability.h"

namespace lego::report {

// The model after one build step (layout/build_order.h), as brickcheck --steps sees it.
struct StepReport {
  int step = 0, new_bricks = 0, bricks = 0;
  double cm_gf = 0;      // -inf (JSON null) when the step has no number
  bool analysed = true;  // false: neither cm_gf nor stands is known (JSON null)
  bool stands = false;
  std::string why;         // when it does not stand
  bool certified = false;  // cm_gf is a certified lower bound (layout::BuildStep::certified)
  bool supports = false;   // the step builds the supports (layout/supports.h)
  int floating = 0;        // bricks placed so far that reach no ground
  // When it does not stand: where the bricks it names are placed (LDraw, LDU), for the booklet's
  // picture of what falls.
  std::vector<std::array<double, 3>> falling_at;
};

// A brick the report names (the weakest contact's two, or what no forces hold), as a builder finds
// it and as --load takes it.
struct NamedBrick {
  std::string part, name;  // "3003", "Brick 2 x 2"
  int step = 0;            // that places it
  std::string where;       // layout/where_on_model.h
  std::array<int, 3> voxel{0, 0, 0};

  std::string words() const;  // "Brick 2 x 2 (3003) at the front left corner of layer 4"
};

// One piece of the model (layout/pieces.h).
struct PieceReport {
  int piece = 1;
  bool grounded = true;  // false: built apart (a submodel in an .mpd)
  int lift = 0;          // layers above the ground it is set at
  int objects = 1;       // separate objects of the mesh in it
  size_t voxels = 0, bricks = 0;
  int components = 1, components_before_joining = 1;
  size_t voxels_added = 0;  // to join thin parts
  int support_columns = 0;  // layout/supports.h
  size_t support_bricks = 0, support_voxels = 0;
  int inside_columns = 0;  // columns in its hollow (layout/supports.h), of the model's inside
  size_t inside_column_voxels = 0;
  double cm_gf = 0;  // -inf (JSON null) when there is no equilibrium
  bool stable = false, steps_stand = false;
  std::string submodel;  // its file in the .mpd; empty for the first piece and in an .ldr
};

struct ConversionReport {
  std::string input, output;
  std::string up;                     // which way was up, and why
  std::vector<std::string> warnings;  // what the mesh named but could not be used
  size_t inside_voxels_coloured = 0;  // inside voxels a hole lays open, given surface colours
  std::vector<PieceReport> pieces;
  int pieces_before_joining = 0;  // components after the first layout, all pieces together
  size_t voxels_added_to_join = 0;
  // Columns added under what hangs so that the model stands (layout/supports.h), all pieces.
  int support_columns = 0;
  size_t support_bricks = 0;
  int support_color = 0;
  // Columns built in the model's hollow before any support (layout/supports.h), all pieces.
  int inside_columns = 0;
  size_t inside_column_voxels = 0;
  // Objects the mesh leaves in the air, stood on support columns (layout/pieces.h); their
  // bricks are in support_bricks, the columns not in support_columns.
  struct Floating {
    int objects = 0, columns = 0;
    size_t voxels = 0;
    int still_floating = 0;
  } floating;
  // Visible voxels built in another colour than theirs (--color-trade, --colors soft), all pieces.
  struct ColourChanges {
    size_t visible = 0, changed = 0;
    double mean_distance = 0, max_distance = 0;  // CIEDE2000, over the changed voxels
  } colour_changes;
  std::array<int, 3> voxels{0, 0, 0};  // W, H, D
  size_t voxels_filled = 0;
  size_t bricks = 0;
  std::map<std::string, int> bricks_by_part;  // "3001": 12
  int components = 0;
  bool single_connected = false;
  double min_cm_gf = 0;
  double cm_gf_initial = 0, cm_gf_final = 0;  // -inf (JSON null) when there is no equilibrium
  std::string status_initial, status_final;
  bool decided = true;  // false: the solver gave up on some piece (UNDECIDED, exit 4)
  std::string solver_final, solver_note_final;  // which solver gave the final C_M, and why
  bool stable = false;
  int iterations = 0, accepted = 0, lp_solves = 0;
  bool refine_out_of_time = false;  // the refinement stopped at its time limit
  // Candidates rejected on a local upper bound, without a whole-model analysis.
  int rejected_by_bound = 0;
  std::vector<std::pair<std::string, double>> seconds;  // per stage, in order
  std::string bottleneck;                               // words, when not stable
  std::vector<NamedBrick> bottleneck_bricks;            // the bricks those words name
  std::vector<StepReport> steps;
  int held_back = 0;  // bricks moved after their layer's step so that a step stands
  bool steps_stand = false;
  bool steps_analysed = true;
  uint64_t seed = 0;
  std::string version;
};

nlohmann::json to_json(const ConversionReport& report);

}  // namespace lego::report
