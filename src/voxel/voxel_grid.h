#pragma once
// A voxel grid with LEGO proportions: a voxel is one stud by one brick (20 × 24 × 20 LDU), so the
// grid is not cubic. y is up.
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace lego::voxel {

enum class Cell : uint8_t {
  Empty,
  Surface,  // crossed by the mesh's surface; carries a color
  Inside,   // inside the mesh; its color is IGNORE (not visible)
};

struct VoxelGrid {
  int width = 0, height = 0, depth = 0;  // x, y, z in voxels
  mesh::Vec3 origin;                     // mesh coordinates of the grid's minimum corner
  double stud = 1, brick = 1.2;          // voxel size in mesh units along x/z and along y
  std::vector<Cell> cells;
  std::vector<mesh::Rgb> color;  // of Surface voxels: area-weighted mean of the surface in them

  size_t index(int x, int y, int z) const { return (size_t(y) * depth + z) * width + x; }
  bool contains(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < width && y < height && z < depth;
  }
  Cell at(int x, int y, int z) const {
    return contains(x, y, z) ? cells[index(x, y, z)] : Cell::Empty;
  }
  size_t count(Cell c) const;
  size_t filled() const { return count(Cell::Surface) + count(Cell::Inside); }
};

}  // namespace lego::voxel
