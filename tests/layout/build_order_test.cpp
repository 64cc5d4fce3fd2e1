// The building order (layout/build_order.h): the same whether the next step's model and system
// are made while a step is decided or after it.
#include <gtest/gtest.h>

#include "layout/build_order.h"
#include "layout/layout.h"
#include "layout/reconfigure.h"
#include "layout/to_assembly.h"
#include "targets.h"

using namespace lego;
using namespace lego::layout;

namespace {

Assembly laid_out(Target t, uint64_t seed) {
  Layout l(std::move(t));
  Random rng(seed);
  ConnectOptions connect;
  connect.ground_connects = true;
  const MergeRules rules;
  initialize_layout(l, rules, rng, connect);
  return to_assembly(l, BrickCatalog::standard(), 72).assembly;
}

void expect_same_order(const Assembly& a, const std::string& name) {
  BuildOrderOptions ahead, one_by_one;
  ahead.max_new_bricks = one_by_one.max_new_bricks = 8;  // many steps, a few bricks each
  one_by_one.side_by_side = false;
  const BuildOrder x = plan_build_order(a, ahead), y = plan_build_order(a, one_by_one);
  EXPECT_EQ(x.step_of, y.step_of) << name;
  EXPECT_EQ(x.analyses, y.analyses) << name;
  EXPECT_EQ(x.held_back, y.held_back) << name;
  ASSERT_EQ(x.steps.size(), y.steps.size()) << name;
  for (size_t k = 0; k < x.steps.size(); ++k) {
    EXPECT_EQ(x.steps[k].stands, y.steps[k].stands) << name << " step " << k + 1;
    EXPECT_EQ(x.steps[k].certified, y.steps[k].certified) << name << " step " << k + 1;
    EXPECT_EQ(x.steps[k].cm_gf, y.steps[k].cm_gf) << name << " step " << k + 1;
  }
}

TEST(BuildOrder, IsTheSameWithTheNextStepsSystemMadeAhead) {
  expect_same_order(laid_out(test::hollow_sphere(7, 2, 4), 3), "a hollow ball");
  expect_same_order(laid_out(test::torus(7, 3), 5), "a torus");
}

// Steps that fall are planned again (their weakest new bricks held back): what was made ahead
// for the step after one that fell is not that step's, and must not be taken for it.
TEST(BuildOrder, IsTheSameWhereStepsFallAndArePlannedAgain) {
  Target t(14, 8, 14);  // a slab on a post at one corner, its far side held by nothing
  for (int y = 0; y < 5; ++y)
    for (int z = 0; z < 2; ++z)
      for (int x = 0; x < 2; ++x) t.set(x, y, z, 4);
  for (int y = 5; y < 8; ++y)
    for (int z = 0; z < 14; ++z)
      for (int x = 0; x < 14; ++x) t.set(x, y, z, y == 7 ? 4 : kIgnore);
  const Assembly a = laid_out(t, 3);
  BuildOrderOptions options;
  options.max_new_bricks = 8;
  const BuildOrder order = plan_build_order(a, options);
  ASSERT_FALSE(order.all_stand()) << "the slab must fall somewhere on its way up";
  ASSERT_GT(order.held_back, 0) << "no step was planned again";
  expect_same_order(a, "a slab on one post");
}

}  // namespace
