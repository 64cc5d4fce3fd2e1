#include "layout/nearby_groups.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "../physics/builders.h"

namespace lego::layout {
namespace {

// A layer of 1x1 bricks, 12 by 10 studs.
Assembly layer_of_bricks() {
  Assembly a;
  for (int x = 0; x < 12; ++x)
    for (int z = 0; z < 10; ++z) test::add(a, "3005", x, 0, z);
  return a;
}

TEST(NearbyGroups, CoverTheBricksInCompactGroupsOfNearlyEqualSize) {
  const Assembly a = layer_of_bricks();
  std::vector<int> all(a.bricks.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = int(i);
  const auto groups = nearby_groups(a, all, 25);
  ASSERT_EQ(groups.size(), 5u);  // 120 bricks, 25 at most
  std::vector<int> seen;
  for (const auto& g : groups) {
    EXPECT_GE(g.size(), 20u);
    EXPECT_LE(g.size(), 25u);
    seen.insert(seen.end(), g.begin(), g.end());
    // Compact: the group's extent holds little more than its own bricks (a cut between equal
    // coordinates leaves a step in its edge); groups drawn at random would span the layer.
    int x0 = 99, x1 = -1, z0 = 99, z1 = -1;
    for (int b : g) {
      x0 = std::min(x0, a.bricks[size_t(b)].min.x);
      x1 = std::max(x1, a.bricks[size_t(b)].min.x);
      z0 = std::min(z0, a.bricks[size_t(b)].min.z);
      z1 = std::max(z1, a.bricks[size_t(b)].min.z);
    }
    EXPECT_LE((x1 - x0 + 1) * (z1 - z0 + 1), int(g.size()) * 3 / 2) << "group of " << g.size();
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, all);
}

TEST(NearbyGroups, FewBricksOrNoLimitMakeOneGroup) {
  const Assembly a = layer_of_bricks();
  EXPECT_EQ(nearby_groups(a, {3, 1, 2}, 25).size(), 1u);
  std::vector<int> all(a.bricks.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = int(i);
  EXPECT_EQ(nearby_groups(a, all, 0).size(), 1u);
  EXPECT_TRUE(nearby_groups(a, {}, 25).empty());
}

}  // namespace
}  // namespace lego::layout
