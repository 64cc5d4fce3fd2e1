#pragma once
// Scenes and thin parts (what paper section 3 leaves out: it assumes one solid object). A mesh
// file often holds several objects, and the voxel grid can cut a thin part (a leg, a handle)
// into voxels that no brick layout joins. Both are handled before and around the layout:
// - split_pieces: the objects are the voxels' 26-connected parts. Those reaching the bottom layer
//   stand on the ground together, one piece; every other object is a piece of its own, lowered
//   to stand on its own bottom (legolize writes it as a submodel to build apart). legolize first
//   stands such objects on columns (stand_floating_objects), so only with --no-supports are
//   there pieces built apart, and then the scene does not stand as the mesh arranges it.
// - initialize_joined: where a part of a piece breaks off after the layout's initialization,
//   voxels are added in the layer above (or below) the gap, so that one brick can span it, and
//   the layout is made again.
#include <cstddef>
#include <optional>
#include <vector>

#include "core/random.h"
#include "layout/layout.h"
#include "layout/merge.h"
#include "layout/reconfigure.h"

namespace lego::layout {

struct Piece {
  Target target;    // the piece's voxels, with its bottom at layer 0
  int lift = 0;     // layers it was lowered by; 0 for the piece on the ground
  int objects = 0;  // separate objects in it
  size_t voxels = 0;
  bool grounded() const { return lift == 0; }
};

// The piece on the ground first (when there is one), then the others by their lowest layer,
// lowest first, then by first voxel. Each piece's target has the grid's width and depth.
std::vector<Piece> split_pieces(const Target& target);

// Objects the mesh leaves in the air (a lid above its pot, a ball inside a cage) stand on columns
// of support voxels (kSupport) down to what is under them or to the ground, so that the scene is
// built where the mesh puts it and stands there, its columns in the support colour for the builder
// to see. Per object, lowest first: a column under the object's mass centre, then each the
// farthest from those chosen while they stand kFloatingColumnSpacing apart, `max_columns` at most;
// two voxels square where the object is that wide. The layout, its refinement and its supports
// then judge the scene as one model.
inline constexpr double kFloatingColumnSpacing = 3;  // voxels between column centres, at least
struct FloatingSupports {
  int objects = 0;         // objects that reached no ground
  int columns = 0;         // columns added under them
  size_t voxels = 0;       // support voxels in those columns
  int still_floating = 0;  // objects that reach no ground even so (resting on each other)
};
FloatingSupports stand_floating_objects(Target& target, int max_columns = 5);

struct JoinedLayout {
  std::optional<Layout> layout;  // always set on return
  ConnectResult connect;         // of the last initialization
  int pieces_before = 0;         // components after the first initialization
  size_t voxels_added = 0;       // to join what broke off
  int rounds = 0;                // the initialization, then one per round of bridges
};

// initialize_layout on the target, with colours exact; where that is not one piece and the rules
// trade colours, Algorithm 5 with the trades; then, while the result is not one piece and a gap can
// be bridged, bridges every part that breaks off to a neighbouring part (its smallest bridge: the
// voxels in the layer above the gap over both sides, in the colour of one side so that a single
// brick may take them), adds them to the layout as 1x1 bricks and goes on with Algorithm 5
// (connect_components) from there, at most `max_rounds` times. The added voxels are in the
// returned layout's target.
JoinedLayout initialize_joined(Target target, const MergeRules& rules, Random& rng,
                               const ConnectOptions& options, int max_rounds = 24);

}  // namespace lego::layout
