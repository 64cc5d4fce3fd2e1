#include <gtest/gtest.h>

#include <cmath>

#include "physics/knob_grip.h"

namespace lego::physics {
namespace {

// Directions (knob_grip.h): 0 +f, 1 +f+s, 2 +s, 3 -f+s, 4 -f, 5 -f-s, 6 -s, 7 +f-s.
uint8_t mask(std::initializer_list<int> directions) {
  uint8_t m = 0;
  for (int d : directions) m |= uint8_t(1u << d);
  return m;
}

const double kWall = 1 / std::sqrt(2.0);

TEST(KnobGrip, TwoOppositePairsGripAtTEach) {
  for (uint8_t m : {mask({0, 2, 4, 6}), mask({1, 3, 5, 7}), mask({0, 4}), mask({1, 5})}) {
    const GripShares& g = grip_shares(m);
    EXPECT_TRUE(g.balanced);
    for (int d = 0; d < kGripDirections; ++d)
      EXPECT_NEAR(g.share[size_t(d)], (m >> d) & 1 ? 1.0 : 0.0, 1e-12) << int(m) << " " << d;
  }
}

TEST(KnobGrip, TwoWallsAndATubeOppositeTheirCorner) {
  // The corner knob of a 2 x N cavity: walls at -f and -s, the tube at +f+s presses √2 as hard.
  const GripShares& g = grip_shares(mask({4, 6, 1}));
  EXPECT_TRUE(g.balanced);
  EXPECT_NEAR(g.share[1], 1.0, 1e-12);
  EXPECT_NEAR(g.share[4], kWall, 1e-12);
  EXPECT_NEAR(g.share[6], kWall, 1e-12);
}

TEST(KnobGrip, OneWallAndTwoTubes) {
  // A knob along the side of a 2 x N cavity: the wall at -s against the tubes at ±f+s.
  const GripShares& g = grip_shares(mask({6, 1, 3}));
  EXPECT_NEAR(g.share[6], 1.0, 1e-12);
  EXPECT_NEAR(g.share[1], kWall, 1e-12);
  EXPECT_NEAR(g.share[3], kWall, 1e-12);
}

TEST(KnobGrip, AContactTheBalanceLeavesUnpressedHoldsNothing) {
  // Four walls and one tube: the walls balance each other at T; the tube cannot be pressed
  // without unloading two of them by more than it adds.
  const GripShares& g = grip_shares(mask({0, 2, 4, 6, 1}));
  EXPECT_NEAR(g.share[1], 0.0, 1e-12);
  for (int d : {0, 2, 4, 6}) EXPECT_NEAR(g.share[size_t(d)], 1.0, 1e-12);
}

TEST(KnobGrip, ContactsOnOneSideKeepTheirT) {
  // The elbow of an L-shaped cavity (a corner brick's) as the part's file draws it: two walls
  // and nothing opposite them.
  const GripShares& g = grip_shares(mask({4, 6}));
  EXPECT_FALSE(g.balanced);
  EXPECT_EQ(g.share[4], 1.0);
  EXPECT_EQ(g.share[6], 1.0);
  EXPECT_EQ(g.share[0], 0.0);
}

TEST(KnobGrip, TurningOrMirroringAKnobTurnsItsShares) {
  for (int m = 0; m < 256; ++m) {
    const GripShares& g = grip_shares(uint8_t(m));
    for (int turn = 0; turn < kGripDirections; turn += 2) {  // quarter turns
      for (bool mirror : {false, true}) {
        auto image = [&](int d) { return ((mirror ? (kGripDirections - d) : d) + turn) % 8; };
        uint8_t mapped = 0;
        for (int d = 0; d < kGripDirections; ++d)
          if (m & (1 << d)) mapped |= uint8_t(1u << image(d));
        const GripShares& h = grip_shares(mapped);
        EXPECT_EQ(g.balanced, h.balanced) << m;
        for (int d = 0; d < kGripDirections; ++d)
          EXPECT_NEAR(g.share[size_t(d)], h.share[size_t(image(d))], 1e-9) << m << " " << d;
      }
    }
  }
}

}  // namespace
}  // namespace lego::physics
