#include "voxel/visibility.h"

#include <array>
#include <deque>

namespace lego::voxel {
std::vector<uint8_t> open_to_outside(int w, int h, int d,
                                     const std::function<bool(size_t)>& filled) {
  auto index = [&](int x, int y, int z) { return (size_t(y) * d + z) * w + x; };
  std::vector<uint8_t> open(size_t(w) * h * d, 0);
  std::deque<std::array<int, 3>> queue;
  auto visit = [&](int x, int y, int z) {
    const size_t i = index(x, y, z);
    if (open[i] || filled(i)) return;
    open[i] = 1;
    queue.push_back({x, y, z});
  };
  for (int y = 0; y < h; ++y)
    for (int z = 0; z < d; ++z)
      for (int x = 0; x < w; ++x)
        if (x == 0 || y == 0 || z == 0 || x == w - 1 || y == h - 1 || z == d - 1) visit(x, y, z);
  while (!queue.empty()) {
    const auto [x, y, z] = queue.front();
    queue.pop_front();
    for (const auto& f : kFaceSteps) {
      const int nx = x + f[0], ny = y + f[1], nz = z + f[2];
      if (nx >= 0 && ny >= 0 && nz >= 0 && nx < w && ny < h && nz < d) visit(nx, ny, nz);
    }
  }
  return open;
}

std::vector<size_t> seen_from_outside(int w, int h, int d,
                                      const std::function<bool(size_t)>& filled) {
  const std::vector<uint8_t> open = open_to_outside(w, h, d, filled);
  std::vector<size_t> seen;
  for (int y = 0; y < h; ++y)
    for (int z = 0; z < d; ++z)
      for (int x = 0; x < w; ++x) {
        const size_t i = (size_t(y) * d + z) * w + x;
        if (!filled(i)) continue;
        for (const auto& f : kFaceSteps) {
          const int nx = x + f[0], ny = y + f[1], nz = z + f[2];
          if (nx < 0 || ny < 0 || nz < 0 || nx >= w || ny >= h || nz >= d ||
              open[(size_t(ny) * d + nz) * w + nx]) {
            seen.push_back(i);
            break;
          }
        }
      }
  return seen;
}

}  // namespace lego::voxel
