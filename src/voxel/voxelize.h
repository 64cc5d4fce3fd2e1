#pragma once
#include <array>
#include <cstddef>

#include "mesh/mesh.h"
#include "voxel/voxel_grid.h"

namespace lego::voxel {

// How big the model comes out, keeping the mesh's aspect: mm_per_unit if set, else fit if set,
// else height_bricks.
struct VoxelizeOptions {
  int height_bricks = 20;           // the model's height in bricks
  std::array<int, 3> fit{0, 0, 0};  // fit within W studs x H bricks x D studs
  double mm_per_unit = 0;           // the mesh's unit in millimetres (a brick is 9.6 mm high)
  size_t max_voxels = 8'000'000;    // refuse grids larger than this (InputError)
  // Refuse grids with a side longer than this (InputError): 4,096 studs are 33 m of LEGO. Within
  // the voxel budget a sliver triangle still made a grid 2,400,000 x 2 x 1 at --height 2 (found
  // by tools/fuzz.sh): 28 s to voxelize, 725,828 bricks, a refinement that never ended.
  int max_side = 4096;
};

// Surface voxels by exact triangle–box overlap (separating axes), so thin walls and sharp
// features keep their voxels; inside voxels by majority vote of ray parity along x, y and z,
// which stays right for meshes with holes, open faces or flipped normals where one axis lies.
VoxelGrid voxelize(const mesh::Mesh& mesh, const VoxelizeOptions& options);

// Keeps the voxels within `shell` voxels of the surface (the surface voxels are the first
// layer): deeper Inside voxels become Empty. shell <= 0 keeps the model solid.
void hollow(VoxelGrid& grid, int shell);

// Inside voxels that can be seen from outside (a mesh with a hole or a non-manifold seam leaves
// its inside open there) become Surface voxels with the colour of the nearest Surface voxel, so
// that the inside colour (IGNORE) never shows. Returns how many were coloured.
size_t colour_seen_inside(VoxelGrid& grid);

}  // namespace lego::voxel
