#include "layout/to_assembly.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/error.h"

namespace lego::layout {

namespace {

// One layer's bricks in building order.
std::vector<int> layer_order(const Layout& layout, std::vector<int> layer) {
  auto by_position = [&](int a, int b) {
    const LayoutBrick &p = layout.brick(a), &q = layout.brick(b);
    return std::pair(p.z, p.x) < std::pair(q.z, q.x);
  };
  std::sort(layer.begin(), layer.end(), by_position);
  std::vector<int> order, around;
  std::vector<char> placed(layout.id_limit(), 0);
  for (int id : layer) {
    const LayoutBrick& b = layout.brick(id);
    around.clear();
    layout.snapped_neighbours(id, around);
    const bool rests = b.y == 0 || std::any_of(around.begin(), around.end(),
                                               [&](int n) { return layout.brick(n).y < b.y; });
    if (rests) {
      placed[id] = 1;
      order.push_back(id);
    }
  }
  for (size_t i = 0; i < order.size(); ++i) {
    around.clear();
    layout.side_neighbours(order[i], around);
    std::sort(around.begin(), around.end(), by_position);
    for (int n : around)
      if (!placed[n]) {
        placed[n] = 1;
        order.push_back(n);
      }
  }
  for (int id : layer)  // bricks held only from above
    if (!placed[id]) order.push_back(id);
  return order;
}

}  // namespace

LayoutAssembly to_assembly(const Layout& layout, const BrickCatalog& catalog, int inside_color,
                           const Loads& loads, int support_color) {
  std::vector<std::vector<int>> layers(size_t(std::max(layout.height(), 0)));
  for (int id : layout.brick_ids()) layers[size_t(layout.brick(id).y)].push_back(id);
  LayoutAssembly out;
  std::vector<int> assembly_index(layout.id_limit(), -1);
  for (auto& layer : layers)
    for (int id : layer_order(layout, std::move(layer))) {
      const LayoutBrick& b = layout.brick(id);
      Brick brick;
      brick.type = catalog.find_by_size(b.length(), b.width(), kPlatesPerBrick);
      if (!brick.type)
        throw std::logic_error("to_assembly: no catalog brick of " + std::to_string(b.width()) +
                               "x" + std::to_string(b.length()));
      brick.rotated = b.size_z > b.size_x;
      brick.min = {b.x, b.y * kPlatesPerBrick, layout.depth() - b.max_z()};
      brick.color = ldraw_color(b.color, inside_color, support_color);
      brick.support = b.color == kSupport;
      brick.source.step = b.y + 1;
      assembly_index[id] = int(out.assembly.bricks.size());
      out.assembly.bricks.push_back(brick);
      out.layout_id.push_back(id);
    }
  out.assembly.ground_height = 0;

  auto weigh = [&](int id, double grams) {
    ExternalLoad load;
    load.brick = assembly_index[id];
    load.force_n = {0, -weight_newton(grams), 0};
    load.spread_over_top_knobs = true;
    out.assembly.loads.push_back(load);
  };
  if (loads.top_grams > 0) {
    int top = -1;
    for (int id : layout.brick_ids()) top = std::max(top, layout.brick(id).y);
    double knobs = 0;
    for (int id : layout.brick_ids())
      if (layout.brick(id).y == top) knobs += layout.brick(id).voxels();
    for (int id : layout.brick_ids())
      if (layout.brick(id).y == top) weigh(id, loads.top_grams * layout.brick(id).voxels() / knobs);
  }
  for (const VoxelLoad& v : loads.at_voxels) {
    const int id = layout.brick_at(v.x, v.y, v.z);
    if (id < 0)
      throw InputError(
          "", 0,
          "--load " + std::to_string(v.x) + "," + std::to_string(v.y) + "," + std::to_string(v.z) +
              ": no brick at that voxel (the grid is " + std::to_string(layout.width()) + " x " +
              std::to_string(layout.height()) + " x " + std::to_string(layout.depth()) + ")");
    weigh(id, v.grams);
  }
  return out;
}

}  // namespace lego::layout
