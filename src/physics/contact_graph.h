#pragma once
// Every contact of an assembly (PHYSICS.md "Connections", "Carried parts", "Ground"), in the
// lattice frame: LDU, y up. Built from the parts' studs, receptacles and body boxes where the
// assembly places them, through spatial hashes, in time linear in the parts.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/assembly.h"
#include "core/budget.h"

namespace lego::physics {

inline constexpr int kGround = -1;  // the "brick" index of the ground in a contact

enum class GroundMode {
  Baseplate,  // the ground has knobs: bricks on it are snapped (the default, PHYSICS.md)
  Table,      // the ground only pushes: normal and support forces, no friction
};

// A rectangle in a contact's plane, in the plane's two other axes (u = kInPlane[axis][0],
// v = kInPlane[axis][1]), LDU; u0 < u1, v0 < v1.
struct Rect {
  double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
  double area() const { return (u1 - u0) * (v1 - v0); }
};

// The in-plane axes of a contact along `axis`, in the order its columns have always had: across
// a horizontal plane x then z, across a vertical one y first.
inline constexpr int kInPlane[3][2] = {{1, 2}, {0, 2}, {1, 0}};

// Where a stud of the lower part touches a receptacle of the upper one (PHYSICS.md), and the
// friction it can hold, as a share of T (physics/knob_grip.h).
struct FrictionPoint {
  double x = 0, y = 0, z = 0;  // lattice frame, LDU
  double share = 1;
};

// Two parts that meet in a plane perpendicular to `direction`, `upper` on its positive side.
// A stud connection (studs > 0): studs of `lower` in receptacles of `upper`; friction, normal and
// support forces. A face contact (studs == 0): normal forces only, but for the ground, which
// also holds sideways (support). An assumed-rigid joint (joint): a carried part ties the two
// together; any force and moment passes, at `joint_point`.
struct Contact {
  int lower = kGround;
  int upper = 0;
  int direction = kPlusY;  // from lower to upper, lattice frame (core/part_shape.h)
  double plane = 0;        // LDU along the direction's axis
  Rect patch;              // where the two bodies' faces meet (normal forces at its corners)
  int studs = 0;
  bool support = false;
  // A face contact where studs of `lower` stand inside the patch without engaging `upper`: the
  // upper part is placed off the lattice (it would sit on the studs, not on the face).
  bool misaligned = false;
  bool joint = false;
  // What kind of joint: assumed rigid (through carried parts, or where two lattices touch), or
  // a Technic shaft in a hole (docs/physics.md, "Joints"): an axle in an axle hole holds every
  // way; a pin, or an axle in a round hole, turns freely about `joint_axis`.
  enum class Kind : uint8_t { Assumed, Turns, Holds };
  Kind joint_kind = Kind::Assumed;
  // Its plane, patch and friction points are in the lattice frame of `upper`, which lies on a
  // turned frame (Brick::frame); otherwise, and for a joint, in the model's.
  bool turned = false;
  Vec3 joint_point{0, 0, 0};    // lattice frame, LDU
  Vec3 joint_axis{0, 0, 0};     // with Kind::Turns: the shaft's axis, a unit vector in the model
  bool joint_friction = false;  // with Kind::Turns: a friction pin or a clip, kFrictionPinMoment
  uint32_t first_point = 0, point_count = 0;  // range in ContactGraph::friction_points
  bool snap() const { return studs > 0; }
};

// Carried parts that touch one another, and what they touch (PHYSICS.md "Carried parts").
struct CarriedGroup {
  std::vector<int> carried;         // indices into Assembly::carried
  std::vector<int> joins;           // analysed, not fixed bricks it touches: tied to one another
  std::vector<int> rests_on_fixed;  // fixed bricks it touches
  bool on_ground = false;           // it reaches the ground plane
  double mass_g = 0;
  Vec3 centre{0, 0, 0};  // of its mass, lattice frame LDU
  // The analysed part that bears its weight: the first it joins where it ties them together
  // (an assumed joint), else the one under its centre of mass, else the one that bears it over
  // the widest area, else the first it joins; -1 when it joins none.
  int bearer = -1;
  // Its weight rests on what is under it (the ground, a fixed part, or analysed parts whose span
  // its centre of mass is over): it needs no connection to stay where it is.
  bool rests = false;
  bool assumed_joint() const { return joins.size() >= 2; }
};

struct ContactGraph {
  GroundMode ground = GroundMode::Baseplate;
  // The table the model rests on (physics/table.h): y = ground_height + ground_slope · (x, z),
  // LDU, lattice frame; level unless the model rests tilted on its lowest points.
  double ground_height = 0;
  std::array<double, 2> ground_slope{0, 0};
  // Its centre of mass is over nothing it could rest on (Table::tips), and no knob holds it to
  // the ground: it tips over.
  bool tips_over = false;
  std::vector<Contact> contacts;
  std::vector<FrictionPoint> friction_points;
  std::vector<std::pair<int, int>> overlaps;  // bricks whose bodies share volume (collisions)
  std::vector<std::vector<int>> contacts_of;  // per brick: indices into `contacts`
  std::vector<char> fixed;                    // per brick: part of the ground
  std::vector<CarriedGroup> carried_groups;
  // The assumed-rigid joints where parts of two lattices touch (docs/what-it-analyses.md, turned
  // lattices): indices into `contacts`.
  std::vector<int> lattice_joints;
  // The assumed-rigid joints where two hinge or turntable halves touch without a line they share
  // (no knuckles found on one): indices into `contacts`.
  std::vector<int> pivot_joints;
  // The Technic joints, a shaft of one part in a hole of another: indices into `contacts`.
  std::vector<int> shaft_joints;

  // Without `assumed_joints`, carried parts and parts of two lattices tie nothing together:
  // what a verdict is without those assumptions (brickcheck --strict). `budget`: stops with
  // OutOfTime when spent.
  static ContactGraph build(const Assembly& assembly, GroundMode ground, bool assumed_joints = true,
                            const Budget* budget = nullptr);
  // Which parts hold which, without the friction points that only the force model reads: what
  // connectivity needs (the audit's passes over what floats), at about four fifths of the cost.
  static ContactGraph connections(const Assembly& assembly, GroundMode ground,
                                  const Budget* budget = nullptr);

  // Whether each contact owes nothing to parts other than its two (or its part and the ground):
  // no carried parts, which tie together every part they touch (studs, faces, shafts, hinges and
  // lattices that touch are pairs). Then the graph of an assembly made of some of these parts is
  // among()'s, when its ground is the same given one (Assembly::ground_height, not found from the
  // parts it has).
  bool pairwise() const;
  // The graph of the assembly made of these parts (`parts`: indices here, ascending; its part k
  // is parts[k] here), as build() makes it, for a pairwise() graph: a build step's contacts
  // without a search of the model for each step (layout/build_order.cpp).
  ContactGraph among(const std::vector<int>& parts) const;
};

// The knob rim radius R (LDU).
inline constexpr double kKnobRimRadius = 6.0;

// The centre of a brick's body (the model's lattice frame, LDU): its boxes' centroid.
Vec3 body_centre(const Brick& brick);

}  // namespace lego::physics
