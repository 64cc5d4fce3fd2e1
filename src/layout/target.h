#pragma once
// What a layout must fill: per voxel, empty, IGNORE (inside, not visible: any color will do), or
// the LDraw color its surface asks for (paper section 3).
#include <cstddef>
#include <vector>

namespace lego::voxel {
struct VoxelGrid;
class Palette;
}  // namespace lego::voxel

namespace lego::layout {

inline constexpr int kEmpty = -1;
inline constexpr int kIgnore = -2;
// A voxel the model does not have, filled to hold up what hangs over it (layout/supports.h): its
// bricks join only each other and take the support colour.
inline constexpr int kSupport = -3;
// Medium Azure: made today, on BrickLink, and seldom a sculpture's own colour.
inline constexpr int kDefaultSupportColor = 322;

// The LDraw colour a layout brick is built in: its own, or the one chosen for IGNORE (inside) or
// support bricks.
inline int ldraw_color(int layout_color, int inside_color, int support_color) {
  return layout_color == kIgnore    ? inside_color
         : layout_color == kSupport ? support_color
                                    : layout_color;
}

struct Target {
  int width = 0, height = 0, depth = 0;  // x, y (layers), z
  std::vector<int> color;                // kEmpty, kIgnore, kSupport or an LDraw color code

  Target() = default;
  Target(int w, int h, int d) : width(w), height(h), depth(d), color(size_t(w) * h * d, kEmpty) {}
  size_t index(int x, int y, int z) const { return (size_t(y) * depth + z) * width + x; }
  bool contains(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < width && y < height && z < depth;
  }
  int at(int x, int y, int z) const { return contains(x, y, z) ? color[index(x, y, z)] : kEmpty; }
  void set(int x, int y, int z, int c) { color[index(x, y, z)] = c; }
  size_t filled() const;
};

// Surface voxels take the palette color nearest to theirs; inside voxels are IGNORE.
Target target_from_voxels(const voxel::VoxelGrid& grid, const voxel::Palette& palette);

}  // namespace lego::layout
