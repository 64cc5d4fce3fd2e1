#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "../../tools/bench/shapes.h"
#include "physics/builders.h"
#include "physics/scaled_lp.h"
#include "physics/solved_blocks.h"
#include "physics/stability.h"

namespace lego::physics {
namespace {

using test::add;
using test::kBrick;

constexpr double kT = 71.658;  // T / g, grams

const Contact& top_contact(const StabilityResult& r) {
  return r.graph.contacts.at(size_t(r.weakest.at(0).contact));
}

TEST(Stability, SingleCantileverOfPhysicsMd) {
  Assembly a;
  int floor = add(a, "3622", 0, 0, 0);
  int beam = add(a, "3008", 0, kBrick, 0);
  for (LpForm form : {LpForm::Scaled, LpForm::MaxMin}) {
    auto r = analyze_stability(a, {.form = form});
    ASSERT_EQ(r.status, StabilityStatus::Solved);
    EXPECT_NEAR(r.cm_gf(), kT - 3.08 / (4 * (2.5 + 1.5 + 0.5)), 0.005);
    EXPECT_NEAR(r.cm_gf(), 71.487, 0.005);
    EXPECT_NEAR(r.cm_newton(), r.cm_gf() * 9.8e-3, 1e-12);
    EXPECT_EQ(top_contact(r).lower, floor);
    EXPECT_EQ(top_contact(r).upper, beam);
    EXPECT_EQ(top_contact(r).studs, 3);
  }
}

TEST(Stability, TheResultNamesItsSolver) {
  // Which solver gave the answer is part of the result (issue 17: a fallback was silent).
  Assembly a;
  add(a, "3622", 0, 0, 0);
  add(a, "3008", 0, kBrick, 0);
  const auto ipm = analyze_stability(a);
  EXPECT_EQ(ipm.stats.solver, "interior point");
  EXPECT_TRUE(ipm.message.empty()) << ipm.message;
  const auto clp = analyze_stability(a, {.method = LpMethod::DualSimplex});
  EXPECT_EQ(clp.stats.solver, "Clp dual simplex");
  EXPECT_NEAR(clp.cm_gf(), ipm.cm_gf(), 1e-6 * ipm.cm_gf());
  EXPECT_TRUE(decided(StabilityStatus::Solved));
  EXPECT_TRUE(decided(StabilityStatus::NoEquilibrium));
  EXPECT_FALSE(decided(StabilityStatus::IterationLimit));
  EXPECT_FALSE(decided(StabilityStatus::NumericalTrouble));
}

TEST(Stability, Figure7Bridges) {
  double previous[2] = {1e9, 1e9};
  double cm[2][13];
  for (int n = 1; n <= 12; ++n) {
    for (int v = 0; v < 2; ++v) {
      const char variant = "ab"[v];
      auto r = analyze_stability(test::figure7_bridge(n, variant));
      ASSERT_EQ(r.status, StabilityStatus::Solved) << variant << n;
      cm[v][n] = r.cm_gf();
      if (n > 1) {
        EXPECT_LT(cm[v][n], previous[v]) << "C_M must fall with length: " << variant << n;
      }
      previous[v] = cm[v][n];
      if (n < 2) continue;
      // Bricks: 0, 1 floor column; 2 .. n+1 the 1x8s; n+2 .. the 1x2s.
      const auto& c = top_contact(r);
      if (variant == 'b') {
        EXPECT_EQ(c.lower, 1) << n;  // the floor brick ...
        EXPECT_EQ(c.upper, 2) << n;  // ... and the first 1x8
      }
      if (variant == 'a') {
        EXPECT_TRUE(c.lower == n + 2 || c.upper == n + 2) << "the first 1x2 at length " << n;
      }
    }
    if (n >= 2) {
      EXPECT_GT(cm[1][n], cm[0][n]) << "(b) beats (a) at " << n;
    }
  }
  EXPECT_GT(cm[0][4], 0);
  EXPECT_LT(cm[0][5], 0);
  EXPECT_GT(cm[1][8], 0);
}

// StableLego's stair (../shared/physical-tests): 2 x 4 bricks each two studs further out. Built,
// 19 stand close to failure and 20 fall. The first joint holds the rest by the 2 x 2 knobs where
// the second brick overlaps the first, tipping about the first's end: the knobs' walls grip at
// T/√2 and their tubes at T where two walls and a tube hold a knob, the wall at T and the tubes
// at T/√2 where one wall and two tubes do (knob_grip.h). With every contact at T it stood at 20.
TEST(Stability, StableLegosStairFallsAtTwenty) {
  auto stair = [](int bricks) {
    Assembly a;
    for (int k = 0; k < bricks; ++k) add(a, "3001", 2 * k, kBrick * k, 0);
    return analyze_stability(a);
  };
  const double w = 1 / std::sqrt(2.0);
  // Levers about the end (x = 4) of the corner knob (x = 2.5) and the middle one (x = 3.5) in
  // each of the two rows.
  const double corner = w * (1.8 + 1.5) + 1 * (1.5 - 0.3 * w);
  const double middle = 1 * 0.5 + w * ((0.5 - 0.3 * w) + (0.5 + 0.3 * w));
  const double levers = 2 * (corner + middle);
  for (int n : {19, 20}) {
    const auto r = stair(n);
    ASSERT_EQ(r.status, StabilityStatus::Solved);
    // The bricks above the first: n - 1 of 2.2 g, their centre n - 2 studs past its end.
    const double moment = (n - 1) * 2.2 * (n - 2);
    EXPECT_NEAR(r.cm_gf(), kT - moment / levers, 1e-3) << n;
    EXPECT_EQ(top_contact(r).upper, 1) << n;
  }
  EXPECT_TRUE(stair(19).stable());
  EXPECT_FALSE(stair(20).stable());
}

TEST(Stability, ColumnNeedsNoFriction) {
  Assembly a;
  for (int i = 0; i < 5; ++i) add(a, "3001", 0, kBrick * i, 0);
  for (GroundMode ground : {GroundMode::Baseplate, GroundMode::Table}) {
    auto r = analyze_stability(a, {.ground = ground});
    ASSERT_EQ(r.status, StabilityStatus::Solved);
    EXPECT_NEAR(r.cm_gf(), kT, 1e-9);
    EXPECT_TRUE(r.weakest.empty());
  }
}

TEST(Stability, HangingBrickSharesItsWeightOverFourPoints) {
  Assembly a;
  add(a, "3005", 0, 0, 0);
  add(a, "3005", 0, kBrick, 0);
  add(a, "3005", 5, 0, 0);
  add(a, "3005", 5, kBrick, 0);
  int beam = add(a, "3009", 0, 2 * kBrick, 0);
  int hanging = add(a, "3005", 2, kBrick, 0);
  auto r = analyze_stability(a, {.brick_capacity = true});
  ASSERT_EQ(r.status, StabilityStatus::Solved);
  EXPECT_NEAR(r.cm_gf(), kT - 0.44 / 4, 1e-6);
  EXPECT_EQ(top_contact(r).lower, hanging);
  EXPECT_EQ(top_contact(r).upper, beam);
  EXPECT_EQ(top_contact(r).point_count, 4u);
  // The beam's cavity holds the hanging brick: its capacity is C_M; the columns carry no pull.
  // (To 1e-3 gf: an interior point method nears a friction that is zero at the optimum and free
  // to be, its bound's multiplier zero too, only as the square root of its gap.)
  ASSERT_EQ(r.brick_capacity.size(), a.bricks.size());
  EXPECT_NEAR(r.brick_capacity[beam] / 9.8, kT - 0.11, 1e-3);
  EXPECT_NEAR(r.brick_capacity[0] / 9.8, kT, 1e-3);
}

// PHYSICS.md "Floating": a floating brick is reported and left out of the LP, and the rest is
// still solved: one brick in the air does not cancel the analysis of the model.
TEST(Stability, FloatingBrickIsReportedAndTheRestSolved) {
  Assembly a;
  add(a, "3001", 0, 0, 0);
  int floating = add(a, "3001", 10, 2 * kBrick, 0);
  auto r = analyze_stability(a);
  EXPECT_EQ(r.status, StabilityStatus::Solved);
  ASSERT_EQ(r.connectivity.floating.size(), 1u);
  EXPECT_EQ(r.connectivity.floating[0], floating);
  EXPECT_EQ(r.connectivity.component_count, 2);
  EXPECT_EQ(r.stats.rows, 6);  // the grounded brick's rows only
  EXPECT_NEAR(r.cm_gf(), kT, 1e-6);
  EXPECT_FALSE(r.stable()) << "a model with floating parts is not stable, whatever its C_M";
  // Nothing on the ground at all: nothing to solve.
  Assembly air;
  air.ground_height = -100;
  add(air, "3001", 0, 0, 0);
  EXPECT_EQ(analyze_stability(air).status, StabilityStatus::Floating);
}

TEST(Stability, TwoTowersJoinedByOneBrick) {
  Assembly a;
  for (int i = 0; i < 3; ++i) {
    add(a, "3003", 0, kBrick * i, 0);
    add(a, "3003", 4, kBrick * i, 0);
  }
  auto apart = analyze_stability(a);
  EXPECT_EQ(apart.connectivity.component_count, 2);
  EXPECT_TRUE(apart.connectivity.all_grounded());
  add(a, "3007", -1, 3 * kBrick, 0, false);  // a 2x8 over both towers
  auto joined = analyze_stability(a);
  EXPECT_EQ(joined.connectivity.component_count, 1);
  ASSERT_EQ(joined.status, StabilityStatus::Solved);
  EXPECT_GT(joined.cm_gf(), 71.0);
  EXPECT_LE(joined.cm_gf(), kT + 1e-9);
}

TEST(Stability, BrickHeldByOneCornerKnob) {
  Assembly a;
  add(a, "3005", 0, 0, 0);
  add(a, "3005", 0, kBrick, 0);
  add(a, "3001", 0, 2 * kBrick, 0);
  auto base = analyze_stability(a);
  ASSERT_EQ(base.status, StabilityStatus::Solved);
  // The 2x4 tips about the 1x1's edge, 1 stud from its centre: 2.2 g·stud held by the corner
  // knob's two walls at T/√2 (levers 0.8 and 0.5 stud) and its tube at T (0.288 stud).
  EXPECT_NEAR(base.cm_gf(), kT - 2.2 / (1.3 / std::sqrt(2.0) + 0.5 - 0.3 / std::sqrt(2.0)), 1e-3);
  for (LpForm form : {LpForm::Scaled, LpForm::MaxMin}) {
    auto table = analyze_stability(a, {.ground = GroundMode::Table, .form = form});
    EXPECT_EQ(table.status, StabilityStatus::NoEquilibrium) << to_string(table.status);
    EXPECT_FALSE(table.stable());
  }
}

// Rotations about the vertical and mirror images of the lattice.
Assembly transformed(const Assembly& a, int quarter_turns, bool mirror) {
  Assembly out = a;
  for (Brick& b : out.bricks) {
    if (mirror) b.min.x = -b.max_x();
    for (int k = 0; k < quarter_turns; ++k) {
      Brick r = b;
      r.rotated = !b.rotated;
      r.min.x = -b.max_z();
      r.min.z = b.min.x;
      b = r;
    }
  }
  return out;
}

Assembly asymmetric_model() {
  Assembly a = test::figure7_bridge(3, 'a');
  add(a, "3001", 0, 3 * kBrick, 0, true);  // turned 2x4 over the floor, sticking out in z
  add(a, "3003", 0, 4 * kBrick, 2);
  add(a, "3004", 12, 3 * kBrick, 0);
  return a;
}

TEST(Stability, InvariantUnderRotationMirrorAndOrder) {
  Assembly a = asymmetric_model();
  auto reference = analyze_stability(a);
  ASSERT_EQ(reference.status, StabilityStatus::Solved);
  for (int turns = 0; turns < 4; ++turns)
    for (bool mirror : {false, true}) {
      auto r = analyze_stability(transformed(a, turns, mirror));
      ASSERT_EQ(r.status, StabilityStatus::Solved);
      EXPECT_NEAR(r.cm, reference.cm, 1e-6 * std::abs(reference.cm)) << turns << mirror;
    }
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3; ++trial) {
    Assembly shuffled = a;
    std::shuffle(shuffled.bricks.begin(), shuffled.bricks.end(), rng);
    EXPECT_NEAR(analyze_stability(shuffled).cm, reference.cm, 1e-6 * std::abs(reference.cm));
  }
}

TEST(Stability, WeightOnTheTipCostsItsMoment) {
  Assembly a;
  add(a, "3622", 0, 0, 0);
  int beam = add(a, "3008", 0, kBrick, 0);
  const double grams = 10;
  // On the last knob of the beam: 4.5 studs past the edge of the floor brick.
  a.loads.push_back({beam, {0, -grams * 1e-3 * 9.8, 0}, false, {7.5, 2.0 * kBrick, 0.5}});
  auto r = analyze_stability(a);
  ASSERT_EQ(r.status, StabilityStatus::Solved);
  EXPECT_NEAR(r.cm_gf(), kT - (3.08 * 1 + grams * 4.5) / (4 * 4.5), 1e-6);
  // Spread over the top knobs: the centre of the knobs is the brick's centre, 1 stud out.
  a.loads.back().spread_over_top_knobs = true;
  EXPECT_NEAR(analyze_stability(a).cm_gf(), kT - (3.08 + grams) / 18, 1e-6);
}

// Towers that narrow upwards (each brick inside the footprint of the one below, so every knob
// under it is engaged and every centre of mass is over its support) need no friction.
TEST(StabilityProperty, NarrowingTowersAreStableWithoutFriction) {
  const auto& types = BrickCatalog::standard().types();
  std::mt19937 rng(42);
  for (int trial = 0; trial < 30; ++trial) {
    Assembly a;
    Brick first;
    first.type = &types[rng() % 11];  // bricks
    first.min = {0, 0, 0};
    a.bricks.push_back(first);
    for (int level = 1; level < 6; ++level) {
      const Brick& below = a.bricks.back();
      std::vector<Brick> fits;
      for (const auto& t : types)
        for (bool rot : {false, true}) {
          Brick b;
          b.type = &t;
          b.min.y = below.top();
          b.rotated = rot;
          if (b.size_x() > below.size_x() || b.size_z() > below.size_z()) continue;
          b.min.x = below.min.x + int(rng() % (below.size_x() - b.size_x() + 1));
          b.min.z = below.min.z + int(rng() % (below.size_z() - b.size_z() + 1));
          fits.push_back(b);
        }
      a.bricks.push_back(fits[rng() % fits.size()]);
    }
    for (GroundMode ground : {GroundMode::Baseplate, GroundMode::Table}) {
      auto r = analyze_stability(a, {.ground = ground});
      ASSERT_EQ(r.status, StabilityStatus::Solved) << trial;
      EXPECT_NEAR(r.cm_gf(), kT, 1e-6) << trial;
      EXPECT_EQ(r.connectivity.component_count, 1);
    }
    // Lift the top brick off its support: it floats.
    a.bricks.back().min.y += 1;
    const auto lifted = analyze_stability(a);
    EXPECT_EQ(lifted.connectivity.floating, std::vector<int>{int(a.bricks.size()) - 1});
    EXPECT_FALSE(lifted.stable());
  }
}

// Both LP forms are the same problem: on random stacks they give the same C_M.
TEST(StabilityProperty, ScaledAndMaxMinFormsAgree) {
  const auto& types = BrickCatalog::standard().types();
  std::mt19937 rng(7);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Assembly a;
    for (int level = 0; level < 8; ++level) {
      Brick b;
      b.type = &types[rng() % 11];
      b.rotated = rng() % 2;
      b.min.y = kBrick * level;
      if (level > 0) {  // overlap the brick below by at least one stud on each axis
        const Brick& below = a.bricks.back();
        b.min.x = below.min.x - b.size_x() + 1 + int(rng() % (below.size_x() + b.size_x() - 1));
        b.min.z = below.min.z - b.size_z() + 1 + int(rng() % (below.size_z() + b.size_z() - 1));
      }
      a.bricks.push_back(b);
    }
    auto s = analyze_stability(a, {.form = LpForm::Scaled});
    auto m = analyze_stability(a, {.form = LpForm::MaxMin});
    ASSERT_EQ(s.status, m.status) << trial;
    if (s.status != StabilityStatus::Solved) continue;
    ++compared;
    EXPECT_NEAR(s.cm, m.cm, 1e-6 * std::max(1.0, std::abs(m.cm))) << trial;
    EXPECT_EQ(s.message, "") << "the interior point method fell back on trial " << trial << ": "
                             << s.message << " (C_M/9.8 = " << m.cm_gf() << ")";
  }
  EXPECT_GT(compared, 5);
}

// `stacks` stacks of `levels` random bricks, 100 studs apart, each brick on the one below by at
// least one stud.
Assembly random_stacks(std::mt19937& rng, int stacks, int levels) {
  const auto& types = BrickCatalog::standard().types();
  Assembly a;
  for (int stack = 0; stack < stacks; ++stack)
    for (int level = 0; level < levels; ++level) {
      Brick b;
      b.type = &types[rng() % 11];
      b.rotated = rng() % 2;
      b.min.y = kBrick * level;
      b.min.x = 100 * stack;
      if (level > 0) {
        const Brick& below = a.bricks.back();
        b.min.x = below.min.x - b.size_x() + 1 + int(rng() % (below.size_x() + b.size_x() - 1));
        b.min.z = below.min.z - b.size_z() + 1 + int(rng() % (below.size_z() + b.size_z() - 1));
      }
      a.bricks.push_back(b);
    }
  return a;
}

// Structures that no force joins are solved apart (equilibrium_blocks.h): a row of random
// stacks, 100 studs apart, gets the C_M, the status, the unbalanced parts and the weakest
// contact of the one LP over all of them, whether each stack is its own LP or they are gathered.
TEST(StabilityProperty, StructuresApartAreSolvedApartAlike) {
  std::mt19937 rng(11);
  int compared = 0, no_equilibrium = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int stacks = 2 + int(rng() % 4);
    Assembly a = random_stacks(rng, stacks, 6);
    // Now and then on a table, with a 2 x 4 on a 1 x 1 column by one corner knob, which tips:
    // no equilibrium in one structure (BrickHeldByOneCornerKnob).
    const bool table = trial % 5 == 4;
    if (table) {
      add(a, "3005", 100 * stacks, 0, 0);
      add(a, "3005", 100 * stacks, kBrick, 0);
      add(a, "3001", 100 * stacks, 2 * kBrick, 0);
    }
    const GroundMode ground = table ? GroundMode::Table : GroundMode::Baseplate;
    const auto whole = analyze_stability(a, {.ground = ground, .block_bodies = 1'000'000});
    for (int least : {1, 7}) {
      const auto apart = analyze_stability(a, {.ground = ground, .block_bodies = least});
      ASSERT_EQ(apart.status, whole.status) << trial;
      EXPECT_EQ(apart.unbalanced, whole.unbalanced) << trial;
      if (whole.status == StabilityStatus::NoEquilibrium) ++no_equilibrium;
      if (whole.status != StabilityStatus::Solved) continue;
      ++compared;
      EXPECT_NEAR(apart.cm, whole.cm, 1e-6 * kT * kGravity) << trial;
      ASSERT_EQ(apart.weakest.empty(), whole.weakest.empty()) << trial;
      if (!whole.weakest.empty() && whole.weakest[0].share > 0.5) {
        EXPECT_EQ(apart.weakest[0].contact, whole.weakest[0].contact) << trial;
      }
      // Every column's force, or none (a structure that needs no friction gives none).
      if (!apart.forces.empty()) {
        EXPECT_EQ(apart.forces.size(), whole.forces.size()) << trial;
      }
    }
  }
  EXPECT_GT(compared, 20);
  EXPECT_GT(no_equilibrium, 0);
}

// The blocks' outcomes, weakest first (StabilityResult::blocks): structures of `block_bodies`
// bodies or more each alone, with the C_M each has analysed by itself; smaller ones gathered.
// Figure 7's bridges of 6 (variant a: 13 bricks) and 9 (variant b: 19 bricks), 100 studs apart,
// and two lone bricks, with blocks of at least 10 bodies.
TEST(StabilityProperty, StructuresSolvedApartAreRankedWeakestFirst) {
  Assembly a;
  const Assembly weak = test::figure7_bridge(6, 'a'), strong = test::figure7_bridge(9, 'b');
  for (const auto& [part, dx] : {std::pair(&strong, 0), std::pair(&weak, 100)})
    for (Brick b : part->bricks) {
      b.min.x += dx;
      a.bricks.push_back(b);
    }
  add(a, "3001", 200, 0, 0);
  add(a, "3001", 300, 0, 0);
  const auto r = analyze_stability(a, {.block_bodies = 10});
  ASSERT_EQ(r.status, StabilityStatus::Solved) << r.message;
  ASSERT_EQ(r.blocks.size(), 3u);
  const double weak_cm = analyze_stability(weak).cm, strong_cm = analyze_stability(strong).cm;
  EXPECT_NEAR(r.blocks[0].cm, weak_cm, 1e-6 * kT * kGravity);
  EXPECT_EQ(r.blocks[0].bricks.size(), weak.bricks.size());
  EXPECT_EQ(r.blocks[0].bricks.front(), int(strong.bricks.size()));
  EXPECT_EQ(r.blocks[0].structures, 1);
  EXPECT_NEAR(r.cm, weak_cm, 1e-6 * kT * kGravity);
  EXPECT_NEAR(r.blocks[1].cm, strong_cm, 1e-6 * kT * kGravity);
  EXPECT_EQ(r.blocks[1].bricks.size(), strong.bricks.size());
  EXPECT_EQ(r.blocks[2].structures, 2);  // the lone bricks, gathered
  EXPECT_EQ(r.blocks[2].bricks,
            (std::vector<int>{int(a.bricks.size()) - 2, int(a.bricks.size()) - 1}));
  EXPECT_LE(r.blocks[1].cm, r.blocks[2].cm);
}

// Large blocks solved two at a time (StabilityOptions::block_jobs, one BLAS thread each) answer as
// one after another: three boxes of 600 to 700 bricks (three structures, not copies of one),
// 100 studs apart, and a stack beside them (a small block of its own), with and without blocks
// an earlier analysis solved.
TEST(StabilityProperty, LargeBlocksSolvedAtOnceAnswerAsOneAfterAnother) {
  Assembly a;
  for (int k = 0; k < 3; ++k)
    for (Brick b : bench::hollow_box_of(600 + 50 * k).bricks) {
      b.min.x += 100 * k;
      a.bricks.push_back(b);
    }
  add(a, "3001", 400, 0, 0);
  add(a, "3001", 401, kBrick, 0);
  const auto one = analyze_stability(a, {.block_bodies = 500, .block_jobs = 1});
  ASSERT_EQ(one.status, StabilityStatus::Solved) << one.message;
  SolvedBlocks solved;
  for (int run = 0; run < 2; ++run) {  // the second run takes every block from the first
    const auto two =
        analyze_stability(a, {.block_bodies = 500, .block_jobs = 2, .solved_blocks = &solved});
    ASSERT_EQ(two.status, StabilityStatus::Solved) << two.message;
    EXPECT_NEAR(two.cm, one.cm, 1e-9 * kT * kGravity);
    ASSERT_EQ(two.forces.size(), one.forces.size());
    for (size_t j = 0; j < one.forces.size(); ++j) ASSERT_NEAR(two.forces[j], one.forces[j], 1e-6);
    ASSERT_EQ(two.weakest.size(), one.weakest.size());
    for (size_t k = 0; k < one.weakest.size(); ++k)
      EXPECT_EQ(two.weakest[k].contact, one.weakest[k].contact);
    EXPECT_EQ(two.stats.rows, one.stats.rows);  // iterations may differ: BLAS threads' last bits
  }
  EXPECT_EQ(solved.reused(), 4);
}

// A structure placed several times (a town's copies of one house) is solved once and each copy
// answers as the first: three copies of Figure 7's bridge and one of a different bridge. The
// copies' C_M are equal, their forces the first's, their weakest contacts their own, and the
// iterations those of the two different bridges alone.
TEST(StabilityProperty, CopiesOfAStructureAreSolvedOnce) {
  const Assembly bridge = test::figure7_bridge(6, 'a'), other = test::figure7_bridge(9, 'b');
  Assembly a;
  for (int k = 0; k < 4; ++k)
    for (Brick b : (k == 2 ? other : bridge).bricks) {
      b.min.x += 100 * k;
      a.bricks.push_back(b);
    }
  SolvedBlocks solved;
  const auto r = analyze_stability(a, {.block_bodies = 10, .solved_blocks = &solved});
  ASSERT_EQ(r.status, StabilityStatus::Solved) << r.message;
  EXPECT_EQ(solved.reused(), 2);
  const auto alone = analyze_stability(bridge), other_alone = analyze_stability(other);
  EXPECT_EQ(r.stats.iterations, alone.stats.iterations + other_alone.stats.iterations);
  ASSERT_EQ(r.blocks.size(), 4u);
  const int n = int(bridge.bricks.size());
  for (int copy : {0, 1, 3}) {
    const auto block = std::find_if(r.blocks.begin(), r.blocks.end(), [&](const BlockOutcome& b) {
      return b.bricks.front() == (copy == 3 ? 2 * n + int(other.bricks.size()) : copy * n);
    });
    ASSERT_NE(block, r.blocks.end()) << copy;
    EXPECT_NEAR(block->cm, alone.cm, 1e-9 * kT * kGravity) << copy;
  }
  EXPECT_EQ(r.blocks[0].cm, r.blocks[1].cm);  // the copies, weakest, in block order
  EXPECT_EQ(r.blocks[1].cm, r.blocks[2].cm);
  EXPECT_LT(r.blocks[0].bricks.front(), r.blocks[1].bricks.front());
  for (const WeakContact& w : r.weakest) {  // the first copy's
    EXPECT_LT(w.upper, n);
    EXPECT_LT(w.lower, n);
  }
}

// Equations that differ in their last bits (a copy placed elsewhere, its lever arms computed
// from other positions) have one key; equations that differ in a millionth's digit do not.
TEST(SolvedBlocksKey, RoundsCoefficientsToAMillionth) {
  const Assembly bridge = test::figure7_bridge(6, 'a');
  StabilityResult r = analyze_contacts(bridge, {});
  const EquilibriumSystem sys = build_equilibrium(bridge, r, {});
  EquilibriumSystem nudged = sys, changed = sys;
  for (double& v : nudged.value) v = std::nextafter(std::nextafter(v, 1e9), 1e9);
  for (double& v : nudged.rhs) v = std::nextafter(v, -1e9);
  changed.value[changed.value.size() / 2] += 1e-5;
  EXPECT_EQ(SolvedBlocks::key_of(nudged), SolvedBlocks::key_of(sys));
  EXPECT_NE(SolvedBlocks::key_of(changed), SolvedBlocks::key_of(sys));
}

// An analysis that reuses the blocks an earlier one solved (SolvedBlocks: the audit analyses a
// model again after carrying a few parts) answers as a fresh one does: the same status, C_M,
// forces, weakest contacts and unbalanced bricks, named by their new indices after a part is
// put before them and one structure changed.
TEST(StabilityProperty, ReusedBlocksAnswerAsAFreshAnalysis) {
  std::mt19937 rng(23);
  int reused = 0, blocks = 0, no_equilibrium = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int stacks = 3 + int(rng() % 3);
    Assembly a = random_stacks(rng, stacks, 5);
    const bool table = trial % 3 == 2;  // with a structure that tips (BrickHeldByOneCornerKnob)
    if (table) {
      add(a, "3005", 100 * stacks, 0, 0);
      add(a, "3005", 100 * stacks, kBrick, 0);
      add(a, "3001", 100 * stacks, 2 * kBrick, 0);
    }
    const StabilityOptions plain{.ground = table ? GroundMode::Table : GroundMode::Baseplate,
                                 .block_bodies = 1};
    SolvedBlocks solved;
    StabilityOptions cached = plain;
    cached.solved_blocks = &solved;
    analyze_stability(a, cached);
    // A part before every other, and the first stack one brick lower.
    Assembly changed;
    add(changed, "3005", -100, 0, 0);
    changed.bricks.insert(changed.bricks.end(), a.bricks.begin(), a.bricks.end());
    changed.bricks.erase(changed.bricks.begin() + 5);
    const int before = solved.reused();
    const auto again = analyze_stability(changed, cached);
    const auto fresh = analyze_stability(changed, plain);
    reused += solved.reused() - before;
    blocks += stacks + (table ? 1 : 0) + 1;
    ASSERT_EQ(again.status, fresh.status) << trial;
    EXPECT_EQ(again.unbalanced, fresh.unbalanced) << trial;
    no_equilibrium += fresh.status == StabilityStatus::NoEquilibrium;
    if (fresh.status != StabilityStatus::Solved) continue;
    EXPECT_NEAR(again.cm, fresh.cm, 1e-9 * kT * kGravity) << trial;
    ASSERT_EQ(again.weakest.size(), fresh.weakest.size()) << trial;
    for (size_t k = 0; k < fresh.weakest.size(); ++k) {
      EXPECT_EQ(again.weakest[k].contact, fresh.weakest[k].contact) << trial;
      EXPECT_EQ(again.weakest[k].lower, fresh.weakest[k].lower) << trial;
      EXPECT_EQ(again.weakest[k].upper, fresh.weakest[k].upper) << trial;
      EXPECT_NEAR(again.weakest[k].share, fresh.weakest[k].share, 1e-9) << trial;
    }
    ASSERT_EQ(again.forces.size(), fresh.forces.size()) << trial;
    for (size_t j = 0; j < fresh.forces.size(); ++j)
      EXPECT_NEAR(again.forces[j], fresh.forces[j], 1e-9 * kT * kGravity) << trial << " " << j;
  }
  // Every stack but the changed one is found again.
  EXPECT_GT(reused, blocks / 2) << blocks;
  EXPECT_GT(no_equilibrium, 0);
}

// Our interior point method converges by itself (no fallback to Clp) and agrees with Clp's
// simplex on C_M and on the weakest contact.
TEST(StabilityProperty, InteriorPointAgreesWithClpSimplex) {
  std::vector<Assembly> models;
  for (int n = 1; n <= 12; ++n)
    for (char v : {'a', 'b'}) models.push_back(test::figure7_bridge(n, v));
  models.push_back(asymmetric_model());
  for (const Assembly& a : models) {
    auto ipm = analyze_stability(a, {.method = LpMethod::InteriorPoint});
    auto simplex = analyze_stability(a, {.method = LpMethod::DualSimplex});
    ASSERT_EQ(ipm.status, StabilityStatus::Solved);
    EXPECT_EQ(ipm.message, "") << "fell back";
    EXPECT_NEAR(ipm.cm, simplex.cm, 1e-6 * std::abs(simplex.cm));
    ASSERT_FALSE(ipm.weakest.empty());
    EXPECT_EQ(ipm.weakest[0].contact, simplex.weakest[0].contact);
  }
}

// The heat map's per-brick capacity on our interior point method (the friction of least norm
// among the distributions reaching C_M, which is unique) matches Clp's QP, without a fallback,
// also with a part placed twice (coincident columns, which Clp's QP once took minutes over).
TEST(StabilityProperty, BrickCapacityAgreesWithClpQp) {
  std::vector<Assembly> models;
  for (int n = 1; n <= 12; ++n)
    for (char v : {'a', 'b'}) models.push_back(test::figure7_bridge(n, v));
  models.push_back(asymmetric_model());
  Assembly twice = test::figure7_bridge(8, 'b');
  twice.bricks.push_back(twice.bricks[3]);
  models.push_back(twice);
  double worst = 0;
  int compared = 0;
  for (const Assembly& a : models) {
    auto ipm = analyze_stability(a, {.brick_capacity = true});
    auto clp = analyze_stability(a, {.method = LpMethod::DualSimplex, .brick_capacity = true});
    ASSERT_EQ(ipm.status, StabilityStatus::Solved);
    EXPECT_EQ(ipm.stats.capacity_solver, "interior point") << ipm.message;
    EXPECT_EQ(clp.stats.capacity_solver, "Clp QP");
    ASSERT_EQ(ipm.brick_capacity.size(), a.bricks.size());
    ASSERT_EQ(clp.brick_capacity.size(), a.bricks.size());
    for (size_t i = 0; i < a.bricks.size(); ++i) {
      worst = std::max(worst, std::abs(ipm.brick_capacity[i] - clp.brick_capacity[i]) / 9.8);
      compared += ipm.brick_capacity[i] < kMaxFrictionLoad;
    }
  }
  EXPECT_GT(compared, 50) << "too few bricks need friction to compare";
  EXPECT_LT(worst, 1e-3) << "gf";
}

// The bench's hollow box of 2,116 bricks (tools/bench/shapes.h): statically indeterminate many
// times over, its normal forces and supports end strictly inside their bounds at no cost. Their Θ
// grew without limit near the capacity QP's optimum, the directions lost their accuracy, and the
// QP ran 49 of its 50 iterations; with the proximal term (interior_point.cpp) it converges in 27,
// and in 19 since it starts from the analysis's forces (brick_capacity).
TEST(StabilityProperty, CapacityQpConvergesOnAnIndeterminateBox) {
  const Assembly a = bench::hollow_box_of(2000);
  auto r = analyze_stability(a, {.brick_capacity = true});
  ASSERT_EQ(r.status, StabilityStatus::Solved);
  EXPECT_EQ(r.stats.capacity_solver, "interior point") << r.message;
  EXPECT_GT(r.stats.capacity_iterations, 0);
  EXPECT_LE(r.stats.capacity_iterations, 23);
  EXPECT_EQ(r.brick_capacity.size(), a.bricks.size());
}

// A wall of 2x4 bricks in running bond with a ledge of one stud at the top: stiff, so w (T over
// the largest friction force) is in the hundreds. Such models ended the interior point method
// on a nearly singular normal matrix (the crate sample failed at some shifts before the gap was
// judged by C_M, scale_objective_options); here it must converge by itself and agree with Clp.
Assembly stiff_wall(int layers) {
  Assembly a;
  for (int layer = 0; layer < layers; ++layer) {
    const int shift = layer % 2 == 0 ? 0 : 2;
    for (int k = 0; k < 4; ++k) add(a, "3001", shift + 4 * k, kBrick * layer, 0);
  }
  const int end = (layers - 1) % 2 == 0 ? 16 : 18;
  add(a, "3001", end - 3, kBrick * layers, 0);  // the ledge: one stud past the wall's end
  return a;
}

TEST(StabilityProperty, StiffModelsAgreeWithClpSimplex) {
  for (int layers : {4, 8, 16}) {
    const Assembly a = stiff_wall(layers);
    auto ipm = analyze_stability(a, {.method = LpMethod::InteriorPoint});
    auto simplex = analyze_stability(a, {.method = LpMethod::DualSimplex});
    ASSERT_EQ(ipm.status, StabilityStatus::Solved) << layers;
    EXPECT_EQ(ipm.message, "") << "fell back";
    const double w = kT / (kT - simplex.cm_gf());
    EXPECT_GT(w, 100) << "not stiff enough to test the gap measure: " << layers;
    EXPECT_NEAR(ipm.cm, simplex.cm, 1e-6 * std::abs(simplex.cm)) << layers;
    ASSERT_FALSE(ipm.weakest.empty());
    EXPECT_EQ(ipm.weakest[0].contact, simplex.weakest[0].contact) << layers;
  }
}

// The gap measure of the scaled LP: never finer than the usual 1 + w; C_M = T·(1 − 1/w), which
// a gap g on w moves by g/(w·(w − 1)) of itself, keeps the tolerance wherever the measure is
// looser than usual; and w itself stays within ten times it (so its cap is recognised).
TEST(ScaledLp, GapMeasuredByItsEffectOnCm) {
  const IpmOptions options = scale_objective_options();
  ASSERT_TRUE(options.gap_scale);
  for (double w : {0.01, 0.5, 1.0, 1.5, 2.0, 3.0, 10.0, 100.0, 551.0, 1e4, 1e6}) {
    const double scale = options.gap_scale(-w), gap = options.tolerance * scale;
    EXPECT_GE(scale, 1 + w) << w;
    EXPECT_LE(gap / w, 10 * options.tolerance * (1 + 1 / w) * (1 + 1e-12)) << w;
    if (scale > 1 + w) {
      EXPECT_LE(gap / (w * (w - 1)), options.tolerance * (1 + 1e-12)) << w;
    }
  }
  EXPECT_GT(options.gap_scale(-551), 552) << "stiff models stop when C_M is exact";
}

// A run that ends at its iteration limit with its best point within `acceptable` says so: the
// note once read "(not 1e-08: )". A best point refused by the final check names that check.
TEST(InteriorPoint, AnAcceptedBestPointNamesTheIterationLimit) {
  IpmProblem lp;  // min −x₁ − x₂  s.t.  x₁ + x₂ + s = 1, all ≥ 0
  lp.rows = 1;
  lp.start = {0, 1, 2, 3};
  lp.index = {0, 0, 0};
  lp.value = {1, 1, 1};
  lp.c = {-1, -1, 0};
  lp.b = {1};
  lp.lower = {0, 0, 0};
  lp.upper.assign(3, std::numeric_limits<double>::infinity());
  IpmOptions options;
  options.max_iterations = 4;
  options.acceptable = 1;  // four steps make it feasible, not yet optimal
  const IpmResult r = solve_interior_point(lp, options);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_NE(r.message.find("(not 1e-08: the limit of 4 iterations)"), std::string::npos)
      << r.message;
  // One step fewer, the best point is within `acceptable` of optimal but not yet feasible to
  // the final check's 1e-6: refused, and the note says so (it once blamed a dropped row, and
  // no row was dropped).
  options.max_iterations = 3;
  const IpmResult early = solve_interior_point(lp, options);
  EXPECT_FALSE(early.converged);
  EXPECT_TRUE(early.message.starts_with("its best point meets the equations only to"))
      << early.message;
}

// --max-seconds: the contact graph and each iteration of the solve stop when the run's budget is
// spent, saying which stage they were in.
TEST(Stability, EveryStageStopsWhenTheBudgetIsSpent) {
  const Assembly a = test::figure7_bridge(4, 'a');
  const Budget spent(0);
  auto stage_stopped = [](auto&& run) -> std::string {
    try {
      run();
    } catch (const OutOfTime& e) {
      return e.stage();
    }
    return "none";
  };
  EXPECT_EQ(stage_stopped([&] { ContactGraph::build(a, GroundMode::Baseplate, true, &spent); }),
            "contact graph");
  EXPECT_EQ(stage_stopped([&] { analyze_stability(a, {.budget = &spent}); }), "contact graph");
  IpmProblem lp;  // min −x  s.t.  x + s = 1, x, s ≥ 0
  lp.rows = 1;
  lp.start = {0, 1, 2};
  lp.index = {0, 0};
  lp.value = {1, 1};
  lp.c = {-1, 0};
  lp.b = {1};
  lp.lower = {0, 0};
  lp.upper.assign(2, std::numeric_limits<double>::infinity());
  IpmOptions options;
  options.budget = &spent;
  EXPECT_EQ(stage_stopped([&] { solve_interior_point(lp, options); }), "solve");
  options.budget = nullptr;
  EXPECT_TRUE(solve_interior_point(lp, options).converged);
  EXPECT_EQ(analyze_stability(a).status, StabilityStatus::Solved);
}

TEST(ContactGraph, FrictionPointsFollowTheCavityShape) {
  Assembly a;
  add(a, "3004", 0, 0, 0);        // 1x2
  add(a, "3004", 0, kBrick, 0);   // 1x2 on it: 2 knobs x 4 points
  add(a, "3003", 10, 0, 0);       // 2x2
  add(a, "3003", 10, kBrick, 0);  // 2x2 on it: 4 knobs x 3 points
  add(a, "3001", 20, 0, 0);       // 2x4 and a 2x4 over it, shifted by a stud:
  add(a, "3001", 21, kBrick, 0);  // 6 knobs x 3 points
  auto g = ContactGraph::build(a, GroundMode::Baseplate);
  std::vector<int> points_by_upper(a.bricks.size(), -1);
  for (const auto& c : g.contacts) {
    if (c.lower != kGround && c.snap()) points_by_upper[size_t(c.upper)] = int(c.point_count);
  }
  EXPECT_EQ(points_by_upper[1], 8);
  EXPECT_EQ(points_by_upper[3], 12);
  EXPECT_EQ(points_by_upper[5], 18);
  auto table = ContactGraph::build(a, GroundMode::Table);
  for (const auto& c : table.contacts) {
    if (c.lower == kGround) {
      EXPECT_EQ(c.point_count, 0u);
    }
  }
}

TEST(ContactGraph, SideContactsAndOverlaps) {
  Assembly a;
  add(a, "3001", 0, 0, 0);
  add(a, "3001", 4, 0, 0);  // touches the first along x = 4
  add(a, "3001", 0, 0, 2);  // touches the first along z = 2
  add(a, "3001", 0, 0, 0);  // coincides with the first
  auto g = ContactGraph::build(a, GroundMode::Baseplate);
  ASSERT_EQ(g.overlaps.size(), 1u);
  EXPECT_EQ(g.overlaps[0], std::make_pair(0, 3));
  int x_sides = 0, z_sides = 0;
  for (const auto& c : g.contacts)
    if (!c.snap() && c.lower != kGround)
      (axis_of(c.direction) == 0 ? x_sides : z_sides) += axis_of(c.direction) != 1;
  EXPECT_GE(x_sides, 1);
  EXPECT_GE(z_sides, 1);
}

}  // namespace
}  // namespace lego::physics
