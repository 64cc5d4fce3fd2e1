#include "layout/target.h"

#include <algorithm>

#include "voxel/palette.h"
#include "voxel/voxel_grid.h"

namespace lego::layout {

size_t Target::filled() const {
  return size_t(std::count_if(color.begin(), color.end(), [](int c) { return c != kEmpty; }));
}

Target target_from_voxels(const voxel::VoxelGrid& g, const voxel::Palette& palette) {
  Target t(g.width, g.height, g.depth);
  for (size_t i = 0; i < g.cells.size(); ++i) {
    if (g.cells[i] == voxel::Cell::Surface)
      t.color[i] = palette.nearest(g.color[i]);
    else if (g.cells[i] == voxel::Cell::Inside)
      t.color[i] = kIgnore;
  }
  return t;
}

}  // namespace lego::layout
