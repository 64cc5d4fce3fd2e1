#pragma once
// Generated assemblies for benchmarks: a hollow box whose walls are laid in bond, with a
// corbelled ledge overhanging one side near the top. Greedy tiling per layer, preferring
// 2x4 bricks turned the other way on alternate layers so the layers interlock.
#include <algorithm>
#include <vector>

#include "core/assembly.h"
#include "core/brick_catalog.h"
#include "physics/connectivity.h"

namespace lego::bench {

inline Assembly hollow_box(int width, int depth, int layers, int wall = 2) {
  const auto& catalog = BrickCatalog::standard();
  Assembly a;
  const int ledge_from = layers - std::max(1, layers / 4);
  for (int layer = 0; layer < layers; ++layer) {
    const int ledge = layer >= ledge_from ? std::min(6, 1 + layer - ledge_from) : 0;
    const int w = width + ledge;
    std::vector<char> want(size_t(w) * depth, 0);
    for (int x = 0; x < w; ++x)
      for (int z = 0; z < depth; ++z) {
        bool ring = x < wall || z < wall || z >= depth - wall || (x >= width - wall && x < width);
        bool on_ledge = x >= width && z >= depth / 3 && z < depth - depth / 3;
        want[size_t(x) * depth + z] = ring || on_ledge;
      }
    auto free_cell = [&](int x, int z) {
      return x >= 0 && z >= 0 && x < w && z < depth && want[size_t(x) * depth + z];
    };
    const bool prefer_x = layer % 2 == 0;
    const int shift = (layer / 2) % 2 * 2;  // stagger joints between layers of the same direction
    for (int xx = 0; xx < w; ++xx)
      for (int zz = 0; zz < depth; ++zz) {
        int x = (xx + shift) % w, z = (zz + shift) % depth;
        if (!free_cell(x, z)) continue;
        for (const char* part : {"3001", "3002", "3003", "3010", "3004", "3005"}) {
          const BrickType* t = catalog.find(part);
          bool placed = false;
          for (bool rotated : {!prefer_x, prefer_x}) {
            int sx = rotated ? t->width : t->length, sz = rotated ? t->length : t->width;
            bool fits = true;
            for (int i = 0; i < sx && fits; ++i)
              for (int k = 0; k < sz && fits; ++k) fits = free_cell(x + i, z + k);
            if (!fits) continue;
            for (int i = 0; i < sx; ++i)
              for (int k = 0; k < sz; ++k) want[size_t(x + i) * depth + z + k] = 0;
            Brick b;
            b.type = t;
            b.rotated = rotated;
            b.min = {x, 3 * layer, z};
            b.color = 15;
            a.bricks.push_back(b);
            placed = true;
            break;
          }
          if (placed) break;
        }
      }
  }
  // Fill bricks left alone on the ledge would float: drop them.
  for (;;) {
    auto g = physics::ContactGraph::build(a, physics::GroundMode::Baseplate);
    auto c = physics::analyze_connectivity(int(a.bricks.size()), g);
    if (c.floating.empty()) break;
    for (auto it = c.floating.rbegin(); it != c.floating.rend(); ++it)
      a.bricks.erase(a.bricks.begin() + *it);
  }
  return a;
}

// A hollow box of about `bricks` bricks.
inline Assembly hollow_box_of(int bricks) {
  // A square ring of 2x4s has about side - 2 bricks per layer; keep the box about as tall
  // (1.2 studs a layer) as it is wide.
  int side = 8;
  while ((side - 2) * side / 1.2 < bricks) side += 2;
  return hollow_box(side, side, std::max(2, bricks / (side - 2)));
}

}  // namespace lego::bench
