#pragma once
// Parts where an assembly places them, in the lattice frame (LDU, y up): what the contact search
// and the force model work on.
#include <array>
#include <vector>

#include "core/assembly.h"

namespace lego::physics {

// Coordinates are snapped to this grid (LDU) so that studs and receptacles of parts placed on
// LDraw's usual positions meet exactly.
inline constexpr double kSnap = 1.0 / 8;

struct WorldShape {
  std::vector<Box> body;
  std::vector<Connector> studs, receptacles, bores;
  std::vector<Shaft> shafts;
  // Where a wheel or a tyre reaches (BrickType::rolls): its round bottom meets a table along a
  // strip, not across its box. Empty for other parts.
  std::vector<Vec3> outline;
};
// In the brick's lattice frame: the model's, or its turned frame (Brick::frame) when it has one.
WorldShape world_shape(const Brick& brick);

// A box turned any way: a carried part's body where the model puts it.
struct OrientedBox {
  Vec3 centre{0, 0, 0};
  std::array<Vec3, 3> axis{};  // unit vectors
  Vec3 half{0, 0, 0};
  Box bounds() const;  // the axis-aligned box around it
};
std::vector<OrientedBox> world_boxes(const CarriedPart& part);
// A carried part's studs where the model puts it, each as stud_box makes it.
std::vector<OrientedBox> world_stud_boxes(const CarriedPart& part, double radius);
// The room a stud takes: `radius` around its axis, a stud's height (4 LDU) along it, in the frame
// its position and direction are in.
Box stud_box(const Connector& stud, double radius);
// Where a carried part reaches (its outline, or its boxes' corners), in the lattice frame.
std::vector<Vec3> world_outline(const CarriedPart& part);
OrientedBox as_oriented(const Box& box);

// A point or a direction of a brick's lattice frame (where world_shape puts it) in the model's
// lattice frame: the same unless the brick lies on a turned frame.
Vec3 to_model(const Brick& brick, const Vec3& point);
Vec3 to_model_direction(const Brick& brick, const Vec3& direction);
// A box of a brick's lattice frame where the model puts it.
OrientedBox to_model(const Brick& brick, const Box& box);
// The axis-aligned box around it in the model's lattice frame.
Box model_bounds(const Brick& brick, const Box& box);

// Whether two boxes come within `gap` of each other (the separating axis test).
bool touch(const OrientedBox& a, const OrientedBox& b, double gap);

}  // namespace lego::physics
