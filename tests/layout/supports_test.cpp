// Supports (layout/supports.h): columns from the ground under what hangs, built first, and
// columns in the model's hollow before them.
#include <gtest/gtest.h>

#include "layout/build_order.h"
#include "layout/merge.h"
#include "layout/reconfigure.h"
#include "layout/refine.h"
#include "layout/supports.h"
#include "layout/to_assembly.h"

using namespace lego;
using namespace lego::layout;

namespace {

// A slab of w x w voxels, `thick` layers, resting on a 2 x 2 post at its corner `post` layers
// tall: it stands only if something holds the far side up.
Target table_on_one_leg(int w, int post, int thick) {
  Target t(w, post + thick, w);
  for (int y = 0; y < post; ++y)
    for (int z = 0; z < 2; ++z)
      for (int x = 0; x < 2; ++x) t.set(x, y, z, 4);
  for (int y = post; y < post + thick; ++y)
    for (int z = 0; z < w; ++z)
      for (int x = 0; x < w; ++x) t.set(x, y, z, y == post + thick - 1 ? 4 : kIgnore);
  return t;
}

Layout initialized(Target t, uint64_t seed = 3) {
  Layout l(std::move(t));
  Random rng(seed);
  ConnectOptions connect;
  connect.ground_connects = true;
  EXPECT_TRUE(initialize_layout(l, {}, rng, connect).single);
  return l;
}

TEST(Supports, AnOverhangGetsColumnsFromTheGroundAndStands) {
  const Target model = table_on_one_leg(14, 5, 3);
  Layout l = initialized(model);
  const BrickCatalog& catalog = BrickCatalog::standard();
  const auto before = physics::analyze_stability(to_assembly(l, catalog, 72).assembly);
  ASSERT_FALSE(before.stable()) << "the slab must not stand on its corner post alone: C_M "
                                << comparable_cm_gf(before);
  const size_t model_bricks = l.brick_count();
  SupportOptions o;
  o.support_color = 14;
  const SupportResult s = add_supports(l, catalog, before, o);
  ASSERT_TRUE(s.stable) << comparable_cm_gf(s.final);
  ASSERT_FALSE(s.columns.empty());
  EXPECT_GT(comparable_cm_gf(s.final), comparable_cm_gf(before));
  // The model's voxels are as they were; every support voxel stands on a support voxel or the
  // ground, and no brick is part support, part model.
  const Target& t = l.target();
  size_t support_voxels = 0;
  for (int y = 0; y < t.height; ++y)
    for (int z = 0; z < t.depth; ++z)
      for (int x = 0; x < t.width; ++x) {
        if (model.at(x, y, z) != kEmpty) {
          EXPECT_EQ(t.at(x, y, z), model.at(x, y, z));
        }
        if (t.at(x, y, z) != kSupport) continue;
        ++support_voxels;
        EXPECT_EQ(model.at(x, y, z), kEmpty);
        if (y > 0) {
          EXPECT_EQ(t.at(x, y - 1, z), kSupport) << x << "," << y << "," << z;
        }
        EXPECT_EQ(l.brick(l.brick_at(x, y, z)).color, kSupport);
      }
  EXPECT_EQ(support_voxels, s.voxels);
  size_t support_bricks = 0;
  for (int id : l.brick_ids()) support_bricks += l.brick(id).color == kSupport;
  EXPECT_EQ(l.brick_count(), model_bricks + support_bricks);
  // In the assembly: flagged, in the support colour, and built first, in a step of their own.
  LayoutAssembly la = to_assembly(l, catalog, 72, {}, o.support_color);
  for (const Brick& b : la.assembly.bricks) EXPECT_EQ(b.support, b.color == 14);
  BuildOrderOptions order;
  const BuildOrder plan = plan_build_order(la.assembly, order);
  EXPECT_TRUE(plan.all_stand());
  for (size_t i = 0; i < la.assembly.bricks.size(); ++i)
    EXPECT_EQ(plan.step_of[i] == 1, la.assembly.bricks[i].support) << i;
}

// A build step is judged on its own bricks: the slab and its corner post are placed, the post
// under the far corner not yet. A column holds the step up; it fits the finished model (not where
// the second post will be), and the finished model stands with it as well.
TEST(Supports, AStepThatFallsIsJudgedOnItsOwnBricks) {
  Target model = table_on_one_leg(14, 5, 3);
  for (int y = 0; y < 5; ++y)
    for (int z = 12; z < 14; ++z)
      for (int x = 12; x < 14; ++x) model.set(x, y, z, 4);
  Layout l = initialized(model);
  const BrickCatalog& catalog = BrickCatalog::standard();
  ASSERT_TRUE(physics::analyze_stability(to_assembly(l, catalog, 72).assembly).stable());
  PlacedBricks step;
  step.placed.assign(l.id_limit(), 0);
  for (int id : l.brick_ids()) {
    const LayoutBrick& b = l.brick(id);
    step.placed[size_t(id)] = !(b.y < 5 && b.x >= 12 && b.z >= 12);
  }
  const auto judged = to_assembly(placed_only(l, step), catalog, 72);
  EXPECT_LT(judged.assembly.bricks.size(), l.brick_count());
  const auto before = physics::analyze_stability(judged.assembly);
  ASSERT_FALSE(before.stable()) << comparable_cm_gf(before);
  const SupportResult s = add_supports(l, catalog, {}, step);
  ASSERT_FALSE(s.columns.empty());
  EXPECT_TRUE(s.stable) << comparable_cm_gf(s.final);
  for (const SupportColumn& c : s.columns)
    EXPECT_FALSE(c.x + c.size_x > 12 && c.z + c.size_z > 12) << "where the second post goes";
  EXPECT_TRUE(physics::analyze_stability(to_assembly(l, catalog, 72).assembly).stable());
  const auto with_columns = to_assembly(placed_only(l, step), catalog, 72);
  EXPECT_TRUE(physics::analyze_stability(with_columns.assembly).stable());
}

TEST(Supports, AModelThatStandsGetsNone) {
  Target cube(4, 4, 4);
  for (int& c : cube.color) c = 4;
  Layout l = initialized(cube);
  const auto ids = l.brick_ids();
  const BrickCatalog& catalog = BrickCatalog::standard();
  const auto r = physics::analyze_stability(to_assembly(l, catalog, 72).assembly);
  ASSERT_TRUE(r.stable());
  const SupportResult s = add_supports(l, catalog, r, {});
  EXPECT_TRUE(s.stable);
  EXPECT_TRUE(s.columns.empty());
  EXPECT_EQ(s.analyses, 0);
  EXPECT_EQ(l.brick_ids(), ids);
}

// A box w x h x w on the ground, its floor and walls one voxel thick, its roof `roof` layers
// (0: open at the top).
Target box_of_walls(int w, int h, int roof) {
  Target box(w, h, w);
  for (int y = 0; y < h; ++y)
    for (int z = 0; z < w; ++z)
      for (int x = 0; x < w; ++x)
        if (y == 0 || y >= h - roof || x == 0 || z == 0 || x == w - 1 || z == w - 1)
          box.set(x, y, z, 4);
  return box;
}

// A closed box, its roof two layers thick (one layer of bricks joins nothing), with a weight on
// the middle of its roof: nothing outside can hold the roof up (the box stands on the ground
// everywhere), a column in its hollow does. It is built as the model's inside, from the floor to
// the roof, and the box's surface is as it was.
TEST(Supports, TheHollowHoldsUpARoofWhereNoColumnFitsOutside) {
  constexpr int w = 14, h = 6;
  const Target box = box_of_walls(w, h, 2);
  Layout l = initialized(box);
  const BrickCatalog& catalog = BrickCatalog::standard();
  SupportOptions o;
  o.loads.at_voxels.push_back({w / 2, h - 1, w / 2, 2000});
  const auto before = physics::analyze_stability(to_assembly(l, catalog, 72, o.loads).assembly);
  ASSERT_FALSE(before.stable()) << "the roof must not hold 2 kg alone: C_M "
                                << comparable_cm_gf(before);
  const SupportResult s = add_supports(l, catalog, before, o);
  ASSERT_TRUE(s.stable) << comparable_cm_gf(s.final);
  ASSERT_FALSE(s.columns.empty());
  EXPECT_EQ(s.inside_columns(), int(s.columns.size()));
  EXPECT_EQ(s.support_columns(), 0);
  EXPECT_EQ(s.voxels, 0u);
  const Target& t = l.target();
  size_t filled = 0;
  for (int y = 0; y < h; ++y)
    for (int z = 0; z < w; ++z)
      for (int x = 0; x < w; ++x) {
        if (box.at(x, y, z) != kEmpty) {
          EXPECT_EQ(t.at(x, y, z), box.at(x, y, z));
          continue;
        }
        EXPECT_NE(t.at(x, y, z), kSupport);
        if (t.at(x, y, z) == kEmpty) continue;
        ++filled;
        EXPECT_EQ(t.at(x, y, z), kIgnore) << x << "," << y << "," << z;
      }
  EXPECT_EQ(filled, s.inside_voxels);
  for (const SupportColumn& c : s.columns) {
    EXPECT_EQ(c.bottom, 1);     // on the floor,
    EXPECT_EQ(c.top(), h - 2);  // under the roof
  }
  // Judged again from scratch, the layout stands with the weight.
  EXPECT_TRUE(physics::analyze_stability(to_assembly(l, catalog, 72, o.loads).assembly).stable());
}

// A box open at the top has no hollow: its inside is the outside, and a column there would be
// a support (none fits: the box stands on the ground).
TEST(Supports, AnOpenBoxHasNoHollowToFill) {
  const Target cup = box_of_walls(10, 4, 0);
  Layout l = initialized(cup);
  const BrickCatalog& catalog = BrickCatalog::standard();
  SupportOptions o;
  o.min_cm_gf = 71;  // more than the cup has: columns are looked for
  const auto r = physics::analyze_stability(to_assembly(l, catalog, 72).assembly);
  const SupportResult s = add_supports(l, catalog, r, o);
  EXPECT_TRUE(s.columns.empty());
  EXPECT_EQ(l.target().color, cup.color);
}

// A column under nothing that fits: a slab hanging from a post with its underside on the ground
// gets nothing, and the layout is left as it was.
TEST(Supports, NoColumnWhereNothingHangsOverEmptyCells) {
  Target t(4, 2, 4);
  for (int z = 0; z < 4; ++z)
    for (int x = 0; x < 4; ++x) t.set(x, 0, z, 4);
  t.set(0, 1, 0, 4);
  Layout l = initialized(t);
  const BrickCatalog& catalog = BrickCatalog::standard();
  const auto r = physics::analyze_stability(to_assembly(l, catalog, 72).assembly);
  SupportOptions o;
  o.min_cm_gf = 1e9;  // asks more than any column could give
  const size_t bricks = l.brick_count();
  const SupportResult s = add_supports(l, catalog, r, o);
  EXPECT_TRUE(s.columns.empty());
  EXPECT_FALSE(s.stable);
  EXPECT_EQ(l.brick_count(), bricks);
}

// A support is taken away whole: no brick is part support, whatever the colour rule, and an
// IGNORE voxel (any colour will do) does not make one either.
TEST(Supports, SupportsMergeOnlyWithSupports) {
  Target t(4, 1, 1);
  t.set(0, 0, 0, kSupport);
  t.set(1, 0, 0, kIgnore);
  t.set(2, 0, 0, kSupport);
  t.set(3, 0, 0, kSupport);
  Layout l(t);
  for (ColorRule rule : {ColorRule::Hard, ColorRule::Soft}) {
    MergeRules rules;
    rules.color = rule;
    EXPECT_FALSE(mergeable(l, l.brick_at(0, 0, 0), l.brick_at(1, 0, 0), rules));
    EXPECT_FALSE(mergeable(l, l.brick_at(1, 0, 0), l.brick_at(2, 0, 0), rules));
    EXPECT_TRUE(mergeable(l, l.brick_at(2, 0, 0), l.brick_at(3, 0, 0), rules));
  }
  Target coloured(2, 1, 1);
  coloured.set(0, 0, 0, kSupport);
  coloured.set(1, 0, 0, 4);
  Layout c(coloured);
  MergeRules soft;
  soft.color = ColorRule::Soft;
  soft.w_c = 0;
  EXPECT_FALSE(mergeable(c, c.brick_at(0, 0, 0), c.brick_at(1, 0, 0), soft));
}

}  // namespace
