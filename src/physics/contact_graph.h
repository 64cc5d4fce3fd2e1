#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "core/assembly.h"

namespace lego::physics {

inline constexpr int kGround = -1;  // the "brick" index of the ground in a contact

enum class GroundMode {
  Baseplate,  // the ground has knobs: bricks on it are snapped (the default, PHYSICS.md)
  Table,      // the ground only pushes: normal and support forces, no friction
};

// Horizontal rectangle on the lattice, in studs; max is exclusive.
struct Rect {
  int x0 = 0, z0 = 0, x1 = 0, z1 = 0;
  int area() const { return (x1 - x0) * (z1 - z0); }
};

// Where a knob of the lower brick touches the cavity of the upper one (PHYSICS.md "Contacts").
struct FrictionPoint {
  double x = 0, z = 0;  // world position in studs
};

// Brick `upper` stands on `lower` (or on the ground) at height `y` (plates).
struct StackedContact {
  int lower = kGround;
  int upper = 0;
  int y = 0;
  Rect overlap;
  int knobs = 0;                              // knobs of `lower` engaged in `upper`'s cavity
  uint32_t first_point = 0, point_count = 0;  // range in ContactGraph::friction_points
  bool snap() const { return knobs > 0; }
};

// Two bricks whose vertical faces lie in one plane and overlap: they can only push.
struct SideContact {
  int negative = 0, positive = 0;  // `negative` lies on the low side of the plane
  int axis = 0;                    // 0: the plane is x = const; 2: z = const
  int plane = 0;                   // studs
  int y0 = 0, y1 = 0;              // plates
  int t0 = 0, t1 = 0;              // studs along the other horizontal axis
};

// Every contact of an assembly, found through a spatial index in O(bricks).
struct ContactGraph {
  GroundMode ground = GroundMode::Baseplate;
  int ground_y = 0;
  std::vector<StackedContact> stacked;
  std::vector<SideContact> sides;
  std::vector<FrictionPoint> friction_points;
  std::vector<std::pair<int, int>> overlaps;  // bricks that share lattice cells (collisions)
  std::vector<std::vector<int>> contacts_of;  // per brick: indices into `stacked`

  static ContactGraph build(const Assembly& assembly, GroundMode ground);
};

// The knob rim radius R in studs (6 LDU).
inline constexpr double kKnobRimRadius = 6.0 / 20.0;

}  // namespace lego::physics
