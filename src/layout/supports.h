#pragma once
// Supports: what the paper leaves for future work (section 8). Where the refined layout still
// cannot stand as asked (thin legs under a heavy body, an overhang, a roof under a weight), the
// model's hollow is used first: columns inside it, from its floor to its ceiling, built as the
// model's inside, which no one sees. Then columns of bricks rise from the ground to what hangs,
// in a colour of their own (kSupport voxels, built in the support colour). Such a column is only
// where the cells under the model are empty down to the ground, so that it can be built first,
// standing on its own, and the model around and on it.
//
// Where they go is what the analysis says: each round takes the brick the weakest contacts hold
// (or one that no forces balance), tries the columns nearest below it and nearest below the centre
// of the mass at its height and above, and keeps the one that raises C_M most (the next weak
// place when none does); inside columns near the weak place are tried first, and the ground's
// only when none of them helps. Rounds go on until the model stands, no column helps, or a limit is
// reached. The result does not depend on `side_by_side`.
#include <functional>
#include <vector>

#include "core/brick_catalog.h"
#include "layout/layout.h"
#include "layout/limits.h"
#include "layout/to_assembly.h"
#include "physics/stability.h"

namespace lego::layout {

// A column of bricks, one per layer, from the ground (a support) or, inside the model, from the
// floor of its hollow to its ceiling: the interior used before anything is added outside. Inside
// columns are built as the model's inside (kIgnore: hidden, merged with the shell by the
// refinement like any inside voxel), not as supports.
struct SupportColumn {
  int x = 0, z = 0;  // minimum voxel
  int size_x = 1, size_z = 1;
  int bottom = 0;  // its first layer: 0 from the ground
  int layers = 0;  // layers bottom .. bottom + layers - 1; the model is on the one above
  bool inside = false;
  int top() const { return bottom + layers; }  // the layer it holds up
};

struct SupportOptions {
  physics::StabilityOptions stability;
  Loads loads;
  int inside_color = 72;
  int support_color = kDefaultSupportColor;
  const Limits* limits = nullptr;  // what columns may use (its support_color counts them)
  double min_cm_gf = 0;            // the model stands when C_M / g exceeds this
  int max_columns = 48;            // columns at most
  // Columns tried per weak place, nearest it and nearest its load's centre (three times as many
  // in a round after one where none helped, before giving up).
  int tries_per_place = 3;
  int weak_places_per_round = 3;  // weak places tried in a round before giving up
  bool side_by_side = true;       // two analyses at once, one thread each
  double max_seconds = 300;       // stop adding after this long
  // After every column kept: the columns so far and the model's C_M / g; may be empty.
  std::function<void(int columns, double cm_gf)> progress;
};

struct SupportResult {
  std::vector<SupportColumn> columns;  // as added, in the layout: supports and inside columns
  size_t voxels = 0;                   // support voxels added
  size_t inside_voxels = 0;            // voxels of the hollow filled by inside columns
  int inside_columns() const;
  int support_columns() const { return int(columns.size()) - inside_columns(); }
  physics::StabilityResult final;  // of the layout with the columns
  bool stable = false;             // final C_M / g > min_cm_gf
  int analyses = 0;
  bool out_of_time = false;
};

// Adds columns to `layout` (a single-connected layout; `current` is its analysis) until it stands.
// Columns that do not raise C_M are not kept; when none helps the layout is as it was.
SupportResult add_supports(Layout& layout, const BrickCatalog& catalog,
                           const physics::StabilityResult& current, const SupportOptions& options);

// The layout's bricks up to a build step: `placed` per layout id (ids past its end are not
// placed), supports always.
struct PlacedBricks {
  std::vector<char> placed;
};
// add_supports for what stands after a build step: the columns fit the finished model, and are
// judged on the placed bricks and the supports, without loads (analysed here first). Columns from
// the ground only: one inside is built with the model's layers, after the step perhaps.
SupportResult add_supports(Layout& layout, const BrickCatalog& catalog,
                           const SupportOptions& options, const PlacedBricks& step);

// The layout as it stands when only `step`'s bricks (and the supports) are placed.
Layout placed_only(const Layout& layout, const PlacedBricks& step);

}  // namespace lego::layout
