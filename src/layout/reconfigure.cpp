#include "layout/reconfigure.h"

namespace lego::layout {

size_t reconfigure(Layout& layout, std::span<const int> critical, int k, const MergeRules& rules,
                   Random& rng) {
  const std::vector<int> region = layout.ring(critical, k);
  std::vector<int> singles;
  for (int id : region) {
    const LayoutBrick b = layout.brick(id);
    layout.remove(id);
    for (int z = b.z; z < b.max_z(); ++z)
      for (int x = b.x; x < b.max_x(); ++x)
        singles.push_back(layout.add(
            LayoutBrick{.x = x, .y = b.y, .z = z, .color = layout.target().at(x, b.y, z)}));
  }
  random_merge(layout, singles, rules, rng);
  return region.size();
}

ConnectResult connect_components(Layout& layout, const MergeRules& rules, Random& rng,
                                 const ConnectOptions& options) {
  ConnectResult result;
  ComponentAnalysis current = analyze_components(layout, rng, options.ground_connects);
  result.components_start = current.count;
  int fails = 0;
  while (current.count > 1 && fails < options.fail_max) {
    ++result.iterations;
    layout.begin_edit();
    const int critical = current.critical;
    reconfigure(layout, std::span(&critical, 1), ring_size(fails, options.ring_step), rules, rng);
    ComponentAnalysis candidate = analyze_components(layout, rng, options.ground_connects);
    if (candidate.count < current.count) {
      layout.commit();
      current = std::move(candidate);
      fails = 0;
      ++result.accepted;
    } else {
      layout.rollback();
      ++fails;
    }
    if (options.progress) options.progress(result.iterations, current.count, fails);
  }
  result.components = current.count;
  result.single = current.count <= 1;
  return result;
}

ConnectResult initialize_layout(Layout& layout, const MergeRules& rules, Random& rng,
                                const ConnectOptions& options) {
  const std::vector<int> all = layout.brick_ids();
  random_merge(layout, all, rules, rng);
  reduce_unit_bricks(layout, rules, rng);
  return connect_components(layout, rules, rng, options);
}

size_t reduce_unit_bricks(Layout& layout, const MergeRules& rules, Random& rng, int tries) {
  std::vector<int> units;
  for (int id : layout.brick_ids())
    if (layout.brick(id).voxels() == 1) units.push_back(id);
  for (size_t i = units.size(); i > 1; --i) std::swap(units[i - 1], units[rng.below(i)]);
  const int start = layout.count(1, 1);
  for (int unit : units)
    for (int t = 0; t < tries && layout.alive(unit) && layout.brick(unit).voxels() == 1; ++t) {
      const int before = layout.count(1, 1);
      const size_t bricks = layout.brick_count();
      layout.begin_edit();
      reconfigure(layout, std::span(&unit, 1), 1 + t / 4, rules, rng);
      if (layout.count(1, 1) < before && layout.brick_count() <= bricks)
        layout.commit();
      else
        layout.rollback();
    }
  return size_t(start - layout.count(1, 1));
}

}  // namespace lego::layout
