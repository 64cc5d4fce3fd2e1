#pragma once
// Small assemblies for physics tests, written the way a builder would describe them.
#include <string>

#include "core/assembly.h"
#include "core/brick_catalog.h"

namespace lego::test {

// Adds the catalog part at lattice min corner (x, y, z); y in plates. Returns its index.
inline int add(Assembly& a, const std::string& part, int x, int y, int z, bool rotated = false,
               int color = 4) {
  Brick b;
  b.type = BrickCatalog::standard().find(part);
  if (!b.type) throw std::runtime_error("no part " + part);
  b.min = {x, y, z};
  b.rotated = rotated;
  b.color = color;
  a.bricks.push_back(b);
  return int(a.bricks.size()) - 1;
}

inline constexpr int kBrick = 3;  // plates per brick

// Paper Figure 7: `length` 1x8 bricks end to end, cantilevered from a floor column of two 1x3
// bricks that holds the first 1x8 by 3 knobs; each joint bridged by a 1x2 under it (variant a)
// or on top of it (variant b).
inline Assembly figure7_bridge(int length, char variant) {
  Assembly a;
  add(a, "3622", 0, 0, 0);
  add(a, "3622", 0, kBrick, 0);
  for (int k = 0; k < length; ++k) add(a, "3008", 8 * k, 2 * kBrick, 0, false, 14);
  for (int k = 1; k < length; ++k)
    add(a, "3004", 8 * k - 1, variant == 'a' ? kBrick : 3 * kBrick, 0);
  return a;
}

}  // namespace lego::test
