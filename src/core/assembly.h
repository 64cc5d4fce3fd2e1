#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/brick.h"
#include "core/part_role.h"

namespace lego {

// A fixed external force on one brick (paper section 7). Forces in newtons; the point in lattice
// units (studs for x and z, plates for y), or spread over the brick's top knobs.
struct ExternalLoad {
  int brick = -1;
  std::array<double, 3> force_n{0, 0, 0};  // y is up: a weight is {0, -m*g, 0}
  bool spread_over_top_knobs = false;
  std::array<double, 3> point{0, 0, 0};  // used when not spread
};

// A placed part whose connections the physics cannot model (PHYSICS.md "Carried parts"): a
// hinge, a wheel, a minifigure, a part at an angle. It keeps its weight and joins what it touches.
struct CarriedPart {
  std::string part;                         // as the catalog names parts: "3938", "s/3068bs01"
  PartRole role = PartRole::NoConnections;  // why its connections are not modelled
  int color = 16;
  SourceRef source;
  double mass_g = 0;
  std::string mass_source;
  std::vector<Box> body;      // in its own frame (LDU)
  std::vector<Vec3> outline;  // PartShape::outline, or empty: the body's corners
  // Its studs, in its own frame: they reach into what holds it (a dish on a bracket's side
  // studs touches the bracket with them, its body a stud's length away).
  std::vector<Connector> studs;
  Pose pose;  // any rotation
  // A hinge or turntable half (BrickType::pivots): it holds what it touches side by side, its
  // fingers or ring engaged in the other half's.
  bool pivots = false;
};
// A part of `type` carried as `role` says: its body, outline, studs and mass are the type's.
CarriedPart carried_part(const BrickType& type, PartRole role, int color, const SourceRef& source,
                         const Pose& pose);

// Bricks on the lattice plus what the physics needs besides them. Both front doors (LDraw files
// and meshes) produce one.
struct Assembly {
  std::vector<Brick> bricks;
  std::vector<CarriedPart> carried;
  std::vector<ExternalLoad> loads;
  // The ground plane: LDU above the origin (the lattice frame, y up); by default the lowest
  // bottom face of the model.
  std::optional<double> ground_height;
  // With ground_height: the table's rise per LDU along x and z, where the model rests tilted
  // (physics/table.h); ground_height is then its height at x = z = 0.
  std::array<double, 2> ground_slope{0, 0};
  // LDU position of lattice point (0,0,0)'s corner, so written files land where they were read.
  std::array<int, 3> origin_ldu{0, 0, 0};
};

// The weight (newtons) of a mass in grams.
inline constexpr double kGravity = 9.8;
inline double weight_newton(double grams) {
  return grams * 1e-3 * kGravity;
}

}  // namespace lego
