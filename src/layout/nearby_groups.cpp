#include "layout/nearby_groups.h"

#include <algorithm>
#include <span>
#include <utility>

namespace lego::layout {

namespace {

using Placed = std::pair<Vec3, int>;  // a brick's centre, the brick

void cut(std::span<Placed> placed, size_t at_most, std::vector<std::vector<int>>& groups) {
  if (placed.size() <= at_most) {
    std::vector<int>& group = groups.emplace_back();
    for (const auto& [c, b] : placed) group.push_back(b);
    std::sort(group.begin(), group.end());
    return;
  }
  Vec3 low = placed.front().first, high = low;
  for (const auto& [c, b] : placed)
    for (size_t k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], c[k]);
      high[k] = std::max(high[k], c[k]);
    }
  size_t axis = 0;
  for (size_t k = 1; k < 3; ++k)
    if (high[k] - low[k] > high[axis] - low[axis]) axis = k;
  std::stable_sort(placed.begin(), placed.end(),
                   [&](const Placed& x, const Placed& y) { return x.first[axis] < y.first[axis]; });
  // Of the groups the bricks need, the low side takes half (rounded down), so that both sides
  // fall into groups of nearly the same size.
  const size_t n = placed.size(), needed = (n + at_most - 1) / at_most;
  const size_t low_side = (n * (needed / 2) + needed - 1) / needed;
  cut(placed.first(low_side), at_most, groups);
  cut(placed.subspan(low_side), at_most, groups);
}

}  // namespace

std::vector<std::vector<int>> nearby_groups(const Assembly& assembly,
                                            const std::vector<int>& bricks, int at_most) {
  std::vector<std::vector<int>> groups;
  if (bricks.empty()) return groups;
  std::vector<Placed> placed;
  for (int b : bricks) placed.emplace_back(model_pose(assembly.bricks[size_t(b)]).origin, b);
  cut(placed, at_most > 0 ? size_t(at_most) : placed.size(), groups);
  return groups;
}

}  // namespace lego::layout
