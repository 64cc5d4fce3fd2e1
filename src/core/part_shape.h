#pragma once
// What the physics needs to know of a part, in the part's own LDraw frame (LDU, -y up, origin
// where the part file has it): its studs, its receptacles and its body (PHYSICS.md "Parts").
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lego {

using Vec3 = std::array<double, 3>;

// One of the six axis directions: 2 * axis + (1 when it points the negative way).
// kUp is LDraw's up (-y) in a part's frame.
inline constexpr int kPlusX = 0, kMinusX = 1, kPlusY = 2, kMinusY = 3, kPlusZ = 4, kMinusZ = 5;
inline constexpr int axis_of(int direction) {
  return direction / 2;
}
inline constexpr double sign_of(int direction) {
  return direction % 2 ? -1.0 : 1.0;
}
inline constexpr int opposite(int direction) {
  return direction ^ 1;
}
inline constexpr int direction_of(int axis, bool negative) {
  return 2 * axis + (negative ? 1 : 0);
}

// A stud (male) or a receptacle (female) of a part. A stud: the centre of its base, `direction`
// the way it points. A receptacle: the centre of the opening where a stud's base comes to rest,
// `direction` the way the opening faces (a stud entering it points the opposite way).
struct Connector {
  Vec3 at{0, 0, 0};
  int direction = kMinusY;
};

// An axis-aligned box, min < max on every axis.
struct Box {
  Vec3 min{0, 0, 0}, max{0, 0, 0};
  double volume() const { return (max[0] - min[0]) * (max[1] - min[1]) * (max[2] - min[2]); }
};

// A Technic connection of a part (docs/physics.md, "Joints"): a hole a pin or an axle goes
// through, or a pin or an axle, along one of the part's axes from `a` to `b` (LDU).
struct Shaft {
  // A friction pin's ridges grip its hole: it turns, but holds a little (docs/physics.md). A
  // knuckle is a hinge or turntable half's round surface on its turning line; a locking hinge's
  // knuckles click in place and hold. A clip grips a bar (3.2 mm across) on its line. A wheel
  // turns on a pin or an axle in its hub, and its rim is gripped by the tyre stretched over it.
  enum class Kind : uint8_t {
    PinHole,
    AxleHole,
    Pin,
    FrictionPin,
    Axle,
    Knuckle,
    LockingKnuckle,
    Clip,
    Bar,
    Hub,
    Rim,
    Tyre
  };
  Kind kind = Kind::PinHole;
  Vec3 a{0, 0, 0}, b{0, 0, 0};
  bool hole() const { return kind == Kind::PinHole || kind == Kind::AxleHole; }
  bool knuckle() const { return kind == Kind::Knuckle || kind == Kind::LockingKnuckle; }
  // What another part's shaft goes into, or meets on its line: a hole, a knuckle, a clip.
  bool receives() const {
    return hole() || knuckle() || kind == Kind::Clip || kind == Kind::Hub || kind == Kind::Tyre;
  }
  // A wheel's hub and rim and a tyre: parts drawn by eye, whose lines may lie a pin's radius
  // apart (docs/physics.md, "Wheels").
  bool wheel() const { return kind == Kind::Hub || kind == Kind::Rim || kind == Kind::Tyre; }
  // Whether `inserted` (a shaft that does not receive) joins `receiver` where they share a line:
  // a pin or an axle in a hole or a wheel's hub, a knuckle on a knuckle, a bar in a clip, a rim in
  // a tyre.
  static bool fits(const Shaft& inserted, const Shaft& receiver) {
    if (inserted.knuckle() || receiver.knuckle()) return inserted.knuckle() && receiver.knuckle();
    if (inserted.kind == Kind::Bar || receiver.kind == Kind::Clip)
      return inserted.kind == Kind::Bar && receiver.kind == Kind::Clip;
    if (inserted.kind == Kind::Rim || receiver.kind == Kind::Tyre)
      return inserted.kind == Kind::Rim && receiver.kind == Kind::Tyre;
    return (receiver.hole() || receiver.kind == Kind::Hub) && !inserted.hole();
  }
  // The axis it lies along (0, 1, 2): the one its two ends differ on most.
  int axis() const {
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(a[size_t(k)] - b[size_t(k)]) > std::abs(a[size_t(axis)] - b[size_t(axis)]))
        axis = k;
    return axis;
  }
};

struct PartShape {
  std::vector<Connector> studs, receptacles;
  // Technic holes, pins and axles; a hinge's knuckles; bars, clips; a wheel's hub and rim, a tyre
  std::vector<Shaft> shafts;
  // Receptacles inside the tubes between four cells (stud4.dat), half a stud off the cells: where
  // a jumper plate's offset stud goes. Not cells: the ground's studs never reach them.
  std::vector<Connector> bores;
  std::vector<Box> body;  // the solid without its studs: one box, or a few
  // The points of its faces farthest out in many directions: where the part reaches when it is
  // turned any way (a tilted round brick's lowest point is not its box's corner). Empty for the
  // catalog's boxes, whose corners are exact.
  std::vector<Vec3> outline;

  Box bounds() const;  // of the body
  double body_volume() const;
};

// The shape of a brick, plate or tile of the catalog's family: a box `length` x `width` studs and
// `height` plates, origin at the top centre, length along x; studs on every top cell (or none, a
// tile), a receptacle under every bottom cell and a bore in every tube between four. It is what the
// library's own files for these parts derive to (tests/parts check it).
PartShape box_brick_shape(int length, int width, int height, bool studs);

}  // namespace lego
