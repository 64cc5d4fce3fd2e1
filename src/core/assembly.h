#pragma once
#include <array>
#include <optional>
#include <vector>

#include "core/brick.h"

namespace lego {

// A fixed external force on one brick (paper section 7). Forces in newtons; the point in lattice
// units (studs for x and z, plates for y), or spread over the brick's top knobs.
struct ExternalLoad {
  int brick = -1;
  std::array<double, 3> force_n{0, 0, 0};  // y is up: a weight is {0, -m*g, 0}
  bool spread_over_top_knobs = false;
  std::array<double, 3> point{0, 0, 0};  // used when not spread
};

// Bricks on the lattice plus what the physics needs besides them. Both front doors (LDraw files
// and meshes) produce one.
struct Assembly {
  std::vector<Brick> bricks;
  std::vector<ExternalLoad> loads;
  // The ground plane in plates; by default the lowest bottom face of the model.
  std::optional<int> ground_y;
  // LDU position of lattice point (0,0,0)'s corner, so written files land where they were read.
  std::array<int, 3> origin_ldu{0, 0, 0};

  int ground_level() const;  // ground_y or the lowest bottom face (0 when empty)
};

// The weight (newtons) of a mass in grams.
inline constexpr double kGravity = 9.8;
inline double weight_newton(double grams) {
  return grams * 1e-3 * kGravity;
}

}  // namespace lego
