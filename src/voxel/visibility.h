#pragma once
// Which cells of a W x H x D grid can be seen from outside: the empty cells reachable from beyond
// the grid through empty cells (6-connected), and the filled cells with a face on one of them.
// Shared by the voxel grid (colouring inside voxels that a hole in the mesh lays open) and the
// bench (counting IGNORE voxels that still show in the finished layout).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace lego::voxel {

// The six face neighbours of a cell, as (dx, dy, dz).
inline constexpr int kFaceSteps[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                         {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};

// Per cell (index (y * D + z) * W + x): 1 for an empty cell open to the outside.
std::vector<uint8_t> open_to_outside(int width, int height, int depth,
                                     const std::function<bool(size_t)>& filled);

// The filled cells with a face on the outside (on the grid's border or on an open empty cell).
std::vector<size_t> seen_from_outside(int width, int height, int depth,
                                      const std::function<bool(size_t)>& filled);

}  // namespace lego::voxel
