// The building order (layout/build_order.h): the same whether the next step's model and system,
// and the models the LP solves ahead, are made while a step is decided or after it; and a step
// the LP solved ahead has the LP's C_M of its own bricks.
#include <gtest/gtest.h>

#include <algorithm>

#include "layout/build_order.h"
#include "layout/layout.h"
#include "layout/reconfigure.h"
#include "layout/to_assembly.h"
#include "physics/stability.h"
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

BuildOrderOptions few_bricks_a_step() {
  BuildOrderOptions o;
  o.max_new_bricks = 8;    // many steps, a few bricks each
  o.solve_ahead = {3, 0};  // solved ahead often, not only on models of hundreds of steps
  return o;
}

// Solved ahead or not, a step's C_M that is not a certificate's bound is the LP's for its bricks.
void expect_exact_where_not_certified(const Assembly& a, const BuildOrder& order,
                                      const BuildOrderOptions& options, const std::string& name) {
  for (size_t k = 0; k < order.steps.size(); ++k) {
    const BuildStep& s = order.steps[k];
    if (!s.analysed || s.certified || s.status != physics::StabilityStatus::Solved) continue;
    Assembly partial;  // as the build order makes a step's model
    partial.origin_ldu = a.origin_ldu;
    partial.ground_height = a.ground_height;
    for (size_t i = 0; i < a.bricks.size(); ++i)
      if (order.step_of[i] <= int(k) + 1) partial.bricks.push_back(a.bricks[i]);
    const physics::StabilityResult r = physics::analyze_stability(partial, options.stability);
    ASSERT_EQ(r.status, physics::StabilityStatus::Solved) << name << " step " << k + 1;
    EXPECT_NEAR(s.cm_gf, r.cm_gf(), 1e-4) << name << " step " << k + 1;
  }
}

void expect_same_order(const Assembly& a, const std::string& name) {
  BuildOrderOptions ahead = few_bricks_a_step(), one_by_one = few_bricks_a_step();
  one_by_one.side_by_side = false;
  const BuildOrder x = plan_build_order(a, ahead), y = plan_build_order(a, one_by_one);
  EXPECT_EQ(x.solved_ahead, y.solved_ahead) << name;
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

// A model the LP solved some steps ahead is taken by the step that has exactly its bricks: the
// C_M of every step the LP gave is the LP's for that step.
TEST(BuildOrder, TakesAModelSolvedAheadOnlyForItsOwnStep) {
  const Assembly a = laid_out(test::hollow_sphere(7, 2, 4), 3);
  const BuildOrderOptions options = few_bricks_a_step();
  const BuildOrder order = plan_build_order(a, options);
  ASSERT_GT(order.solved_ahead, 0) << "no step was solved ahead";
  expect_exact_where_not_certified(a, order, options, "a hollow ball");
  BuildOrderOptions never = options;
  never.solve_ahead.steps = 0;
  EXPECT_EQ(plan_build_order(a, never).solved_ahead, 0);
}

// The LPs the order solved are counted, certified steps not among them: every analysis without
// certificates, and with them the steps left uncertified (those solved ahead, the weakest step's).
TEST(BuildOrder, CountsTheLpsItSolves) {
  const Assembly a = laid_out(test::hollow_sphere(7, 2, 4), 3);
  BuildOrderOptions options = few_bricks_a_step();
  const BuildOrder order = plan_build_order(a, options);
  ASSERT_TRUE(order.all_stand());
  const auto by_lp = std::count_if(order.steps.begin(), order.steps.end(),
                                   [](const BuildStep& s) { return s.analysed && !s.certified; });
  ASSERT_GT(order.certified_steps(), 0);
  EXPECT_EQ(order.lp_solves, by_lp);
  EXPECT_GT(order.lp_seconds, 0);
  EXPECT_LT(order.lp_seconds, order.seconds);
  options.certify = false;
  const BuildOrder every = plan_build_order(a, options);
  EXPECT_EQ(every.certified_steps(), 0);
  EXPECT_EQ(every.lp_solves, every.analyses);
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
  const BuildOrderOptions options = few_bricks_a_step();
  const BuildOrder order = plan_build_order(a, options);
  ASSERT_FALSE(order.all_stand()) << "the slab must fall somewhere on its way up";
  ASSERT_GT(order.held_back, 0) << "no step was planned again";
  expect_same_order(a, "a slab on one post");
  expect_exact_where_not_certified(a, order, options, "a slab on one post");
}

}  // namespace
