#pragma once
// A layout as an Assembly of catalog bricks, ready for the stability analysis and LDraw output.
#include <vector>

#include "core/assembly.h"
#include "core/brick_catalog.h"
#include "layout/layout.h"

namespace lego::layout {

// External weights (paper section 7): spread over the top knobs of the model (the bricks of its
// highest layer, by knob count), or on the brick at a voxel.
struct VoxelLoad {
  int x = 0, y = 0, z = 0;  // voxel; y is the layer
  double grams = 0;
};
struct Loads {
  double top_grams = 0;
  std::vector<VoxelLoad> at_voxels;
};

struct LayoutAssembly {
  Assembly assembly;
  std::vector<int> layout_id;  // per assembly brick: its id in the layout
};

// Bricks layer by layer, each layer a build step (Brick::source.step; layout/build_order.h then
// orders the steps so that each stands), in building order: first the bricks that rest on the
// layer below, then outward from them through side neighbours. Lattice z runs opposite to voxel
// z, which turns the model a half turn about x instead of mirroring it (LDraw is right-handed with
// -y up). IGNORE bricks get `inside_color`, supports `support_color` (and Brick::support). Throws
// InputError when a voxel load names an empty voxel.
LayoutAssembly to_assembly(const Layout& layout, const BrickCatalog& catalog, int inside_color,
                           const Loads& loads = {}, int support_color = kDefaultSupportColor);

}  // namespace lego::layout
