#pragma once
// Voxel targets built directly, for layout tests.
#include <cmath>

#include "core/random.h"
#include "layout/target.h"

namespace lego::test {

// Random voxels: each filled with probability `fill`, IGNORE or one of `colors` colors (1, 2...).
inline layout::Target random_target(int w, int h, int d, double fill, int colors, uint64_t seed) {
  layout::Target t(w, h, d);
  Random rng(seed);
  for (int& c : t.color)
    if (rng.unit() < fill)
      c = colors == 0 || rng.below(3) == 0 ? layout::kIgnore : 1 + int(rng.below(size_t(colors)));
  return t;
}

// A ball of radius r voxels (in voxel index units on all axes), hollowed to `shell` voxels: the
// outermost voxels colored `color`, deeper ones IGNORE.
inline layout::Target hollow_sphere(int r, int shell, int color) {
  const int n = 2 * r + 1;
  layout::Target t(n, n, n);
  for (int y = 0; y < n; ++y)
    for (int z = 0; z < n; ++z)
      for (int x = 0; x < n; ++x) {
        const double d = std::hypot(x - r, y - r, z - r);
        if (d > r + 0.5 || d <= r + 0.5 - shell) continue;
        t.set(x, y, z, d > r - 0.5 ? color : layout::kIgnore);
      }
  return t;
}

// A torus lying flat: ring radius R, tube radius r, in voxels.
inline layout::Target torus(int R, int r) {
  const int w = 2 * (R + r) + 1, h = 2 * r + 1;
  layout::Target t(w, h, w);
  const int c = R + r;
  for (int y = 0; y < h; ++y)
    for (int z = 0; z < w; ++z)
      for (int x = 0; x < w; ++x) {
        const double q = std::hypot(x - c, z - c) - R;
        if (std::hypot(q, y - r) <= r + 0.5) t.set(x, y, z, layout::kIgnore);
      }
  return t;
}

// Two towers side by side, a gap between them, joined by a bridge at the top (joined = true) or
// not at all: two separate objects.
inline layout::Target two_towers(int size, int height, int gap, bool joined) {
  const int w = 2 * size + gap;
  layout::Target t(w, height, size);
  for (int y = 0; y < height; ++y)
    for (int z = 0; z < size; ++z)
      for (int x = 0; x < w; ++x) {
        const bool tower = x < size || x >= size + gap;
        if (tower || (joined && y == height - 1)) t.set(x, y, z, layout::kIgnore);
      }
  return t;
}

// A hollow box of w x h x d voxels with walls `wall` voxels thick (open nowhere).
inline layout::Target hollow_box(int w, int h, int d, int wall) {
  layout::Target t(w, h, d);
  for (int y = 0; y < h; ++y)
    for (int z = 0; z < d; ++z)
      for (int x = 0; x < w; ++x) {
        const int depth_in = std::min({x, y, z, w - 1 - x, h - 1 - y, d - 1 - z});
        if (depth_in < wall) t.set(x, y, z, depth_in == 0 ? 15 : layout::kIgnore);
      }
  return t;
}

}  // namespace lego::test
