#include "layout/components.h"

#include <algorithm>

namespace lego::layout {

ComponentAnalysis analyze_components(const Layout& layout, Random& rng, bool ground_connects) {
  ComponentAnalysis result;
  result.component.assign(layout.id_limit(), -1);
  std::vector<int> stack, around;
  const std::vector<int> ids = layout.brick_ids();
  // One component from the seeds: a depth-first search over snaps.
  auto flood = [&](const std::vector<int>& seeds) {
    const int id = result.count++;
    int size = 0;
    for (int s : seeds) {
      result.component[s] = id;
      stack.push_back(s);
    }
    while (!stack.empty()) {
      const int b = stack.back();
      stack.pop_back();
      ++size;
      around.clear();
      layout.snapped_neighbours(b, around);
      for (int n : around)
        if (result.component[n] < 0) {
          result.component[n] = id;
          stack.push_back(n);
        }
    }
    result.sizes.push_back(size);
  };
  if (ground_connects) {  // the ground's component first: every brick on it starts the search
    std::vector<int> on_ground;
    for (int id : ids)
      if (layout.brick(id).y == 0) on_ground.push_back(id);
    if (!on_ground.empty()) flood(on_ground);
  }
  for (int start : ids)
    if (result.component[start] < 0) flood({start});
  if (result.count <= 1) return result;

  std::vector<int> candidates, weights, seen;
  long total = 0;
  for (int b : ids) {
    around.clear();
    layout.neighbours(b, around);
    seen.clear();
    for (int n : around)
      if (result.component[n] != result.component[b]) seen.push_back(result.component[n]);
    std::sort(seen.begin(), seen.end());
    const int n_i = int(std::unique(seen.begin(), seen.end()) - seen.begin());
    if (n_i == 0) continue;
    candidates.push_back(b);
    weights.push_back(n_i);
    total += n_i;
  }
  if (total == 0) {
    // Components that touch nothing of each other (two separate objects): no brick is critical,
    // so reconfigure at a random brick; nothing will join them, and Algorithm 5 says so.
    result.critical = ids[rng.below(ids.size())];
    return result;
  }
  long pick = long(rng.below(size_t(total)));
  for (size_t i = 0; i < candidates.size(); ++i) {
    pick -= weights[i];
    if (pick < 0) {
      result.critical = candidates[i];
      break;
    }
  }
  return result;
}

}  // namespace lego::layout
