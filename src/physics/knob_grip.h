#pragma once
// How hard each contact of a knob grips it (docs/physics.md, "How a knob is held").
//
// A knob is held by the features of the cavity it stands in: walls, the pins of a part one stud
// wide, tubes. They press on its rim because the fit is tight, and the friction each contact can
// give is proportional to how hard it presses. Those pressures are a preload the knob carries in
// equilibrium: they balance one another in the plane of the rim. The paper's T is the friction of
// the contact that presses hardest; the others press as hard as the knob's balance lets them.
// A knob pinched by two opposite pairs (any knob of a part one stud wide, a knob among four
// tubes) has all its contacts at T. A knob held by two walls and the tube opposite their corner
// has the tube at T and each wall at T/√2; by one wall and two tubes, the wall at T and each tube
// at T/√2.
#include <array>
#include <cstdint>

namespace lego::physics {

// The eight directions from a knob's centre to its contacts, in the plane of its rim: along the
// plane's first axis, its second, and the diagonals, counter-clockwise from the first axis.
inline constexpr int kGripDirections = 8;
// (first axis, second axis) steps of each direction.
inline constexpr int kGripStep[kGripDirections][2] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                                      {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};

// Each contact's share of T for a knob touched in the directions set in `mask` (bit d for
// direction d): the largest preload in balance with no contact above T, as fractions of T.
// Contacts that cannot balance one another (all on one side of the knob: the part's drawn
// features show only part of the cavity) keep T each, as the paper has every contact.
struct GripShares {
  std::array<double, kGripDirections> share{};
  bool balanced = true;  // false: the contacts could not balance, and each keeps T
};
const GripShares& grip_shares(uint8_t mask);

}  // namespace lego::physics
