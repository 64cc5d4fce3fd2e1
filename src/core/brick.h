#pragma once
#include <string>

#include "core/brick_catalog.h"
#include "core/lattice.h"

namespace lego {

// Where a brick came from when it was read from LDraw (empty file when generated).
struct SourceRef {
  std::string file;
  int line = 0;
  int step = 0;  // 1-based build step of the main model, 0 when unknown
};

// A brick on the lattice: the lattice cell of its minimum corner, turned 0 or 90 degrees about
// the vertical. At 0 degrees its length runs along x; at 90 degrees along z.
struct Brick {
  const BrickType* type = nullptr;
  LatticePoint min;  // x, z in studs; y in plates (the bottom face)
  bool rotated = false;
  int color = 16;  // LDraw colour code
  SourceRef source;

  int size_x() const { return rotated ? type->width : type->length; }
  int size_z() const { return rotated ? type->length : type->width; }
  int height() const { return type->height; }
  int max_x() const { return min.x + size_x(); }  // exclusive
  int max_z() const { return min.z + size_z(); }
  int top() const { return min.y + height(); }
  double mass_g() const { return type->mass_g; }
};

}  // namespace lego
