#include "physics/local_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "builders.h"

namespace lego::physics {
namespace {

using test::add;
using test::kBrick;

// A one-stud-deep wall (8 studs, `layers` high) carrying a beam of two courses of 1x4 bricks in
// running bond that reaches 16 studs out over its end, loaded at the tip: the beam's joints near
// the wall bind, and forces have many paths through the wall.
Assembly loaded_beam(int layers, double tip_newton) {
  Assembly a;
  auto course = [&](int l, int length) {
    if (l % 2 == 0) {
      for (int x = 0; x < length; x += 4) add(a, "3010", x, kBrick * l, 0);
    } else {
      add(a, "3004", 0, kBrick * l, 0);
      for (int x = 2; x + 4 < length; x += 4) add(a, "3010", x, kBrick * l, 0);
      add(a, "3004", length - 2, kBrick * l, 0);
    }
  };
  for (int l = 0; l < layers; ++l) course(l, 8);
  course(layers, 24);
  course(layers + 1, 24);
  a.loads.push_back({.brick = int(a.bricks.size()) - 1,
                     .force_n = {0, -tip_newton, 0},
                     .point = {23.5, double(kBrick * (layers + 2)), 0.5}});
  return a;
}

// The assembly with, in `layer`, the 1x4 bricks at `x` and x + 4 merged into a 1x8 (`merge`) or
// the 1x4 at `x` split into two 1x2 (otherwise), and the bricks listed in reverse order.
Assembly rejoined(const Assembly& model, int layer, int x, bool merge) {
  Assembly out;
  int loaded = -1;
  for (size_t i = 0; i < model.bricks.size(); ++i) {
    const Brick& b = model.bricks[i];
    if (b.min.y == kBrick * layer && (b.min.x == x || (merge && b.min.x == x + 4))) continue;
    if (int(i) == model.loads.front().brick) loaded = int(out.bricks.size());
    out.bricks.push_back(b);
  }
  if (merge) {
    add(out, "3008", x, kBrick * layer, 0);
  } else {
    add(out, "3004", x, kBrick * layer, 0);
    add(out, "3004", x + 2, kBrick * layer, 0);
  }
  std::reverse(out.bricks.begin(), out.bricks.end());
  out.loads = model.loads;
  out.loads.front().brick = int(out.bricks.size()) - 1 - loaded;
  return out;
}

constexpr double kTolerance = 1e-5 * kMaxFrictionLoad;  // well above the solver's 1e-6 relative

TEST(LocalBounds, SameAssemblyGivesItsOwnCm) {
  const Assembly wall = loaded_beam(4, 0.05);
  const StabilityResult result = analyze_stability(wall);
  ASSERT_EQ(result.status, StabilityStatus::Solved);
  ASSERT_FALSE(result.forces.empty());
  const CmBounds bounds = bound_cm_locally(wall, result, wall);
  EXPECT_TRUE(bounds.valid);
  EXPECT_EQ(bounds.changed_bricks, 0);
  EXPECT_EQ(bounds.lower, result.cm);
  EXPECT_EQ(bounds.upper, result.cm);
}

// On every rejoining of every layer: lower ≤ exact C_M ≤ upper, for rings 0 to 3; with a ring
// that takes in the whole wall both bounds are the exact value.
TEST(LocalBounds, BoundTheExactCm) {
  const Assembly wall = loaded_beam(4, 0.05);
  const StabilityResult result = analyze_stability(wall);
  ASSERT_EQ(result.status, StabilityStatus::Solved);
  int not_better = 0, not_better_known = 0, lower_finite = 0, lower_exact = 0;
  struct Change {
    int layer, x;
    bool merge;
  };
  std::vector<Change> changes;
  for (int x = 0; x <= 16; x += 4) changes.push_back({4, x, true});
  for (int x = 2; x <= 14; x += 4) changes.push_back({5, x, true});
  for (int x = 0; x <= 20; x += 4) changes.push_back({4, x, false});
  for (int layer : {0, 2})
    changes.push_back({layer, 0, true}), changes.push_back({layer, 4, false});
  for (const Change& change : changes) {
    const Assembly after = rejoined(wall, change.layer, change.x, change.merge);
    const StabilityResult exact = analyze_stability(after);
    if (!exact.connectivity.all_grounded()) continue;  // a joint through both courses
    ASSERT_EQ(exact.status, StabilityStatus::Solved);
    for (int ring : {0, 1, 2, 3, 40}) {
      const CmBounds b = bound_cm_locally(wall, result, after, {.ring = ring, .stability = {}});
      SCOPED_TRACE(testing::Message() << "layer " << change.layer << " x " << change.x
                                      << (change.merge ? " merged" : " split") << " ring " << ring);
      ASSERT_TRUE(b.valid);
      EXPECT_EQ(b.changed_bricks, change.merge ? 1 : 2);
      EXPECT_LE(b.lower, exact.cm + kTolerance);
      EXPECT_GE(b.upper, exact.cm - kTolerance);
      if (ring == 40) {
        EXPECT_EQ(b.region_bricks, int(after.bricks.size()));
        EXPECT_NEAR(b.lower, exact.cm, kTolerance);
        EXPECT_NEAR(b.upper, exact.cm, kTolerance);
      } else if (b.region_bricks < int(after.bricks.size()) && exact.cm <= result.cm) {
        // Refinement rejects what is not better than the current C_M: the upper bound can
        // tell that without the whole model's LP.
        not_better_known += b.upper <= result.cm + kTolerance;
        ++not_better;
      }
      // The lower bound is finite only where the fixed boundary forces can carry the region
      // (not when its weight changed and it does not reach the ground); there it is the exact
      // value here, from a part of the model.
      if (b.region_bricks < int(after.bricks.size()) && b.lower > -1e300) {
        ++lower_finite;
        lower_exact += std::abs(b.lower - exact.cm) < kTolerance;
      }
    }
  }
  // A measurement more than a property, but it must not silently drop to nothing.
  EXPECT_GT(not_better_known, not_better / 2) << not_better_known << " of " << not_better;
  EXPECT_GT(lower_exact, 0) << lower_finite;
}

TEST(LocalBounds, OpenWithoutTheAnalysedForces) {
  const Assembly wall = loaded_beam(4, 0.05);
  StabilityResult result = analyze_stability(wall);
  result.forces.clear();
  const CmBounds b =
      bound_cm_locally(wall, result, rejoined(wall, 4, 4, true), {.ring = 1, .stability = {}});
  EXPECT_FALSE(b.valid);
  EXPECT_EQ(b.lower, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(b.upper, std::numeric_limits<double>::infinity());
}

// A load outside the region that differs between the two is not the same model there.
TEST(LocalBounds, OpenWhenTheOutsideChanged) {
  const Assembly wall = loaded_beam(4, 0.05);
  const StabilityResult result = analyze_stability(wall);
  Assembly after = rejoined(wall, 0, 0, true);
  after.loads.front().force_n[1] *= 2;
  EXPECT_FALSE(bound_cm_locally(wall, result, after, {.ring = 0, .stability = {}}).valid);
}

}  // namespace
}  // namespace lego::physics
