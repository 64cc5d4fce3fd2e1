#include "core/assembly.h"

#include <cmath>
#include <utility>

namespace lego {

int Pose::turn(int direction) const {
  const int a = axis_of(direction);
  for (int r = 0; r < 3; ++r) {
    const double m = rotation[3 * r + a];
    if (std::abs(m) > 0.5) return direction_of(r, (m < 0) != (sign_of(direction) < 0));
  }
  return direction;
}

CarriedPart carried_part(const BrickType& type, PartRole role, int color, const SourceRef& source,
                         const Pose& pose) {
  CarriedPart c;
  c.part = type.part;
  c.role = role;
  c.color = color;
  c.source = source;
  c.mass_g = type.mass_g;
  c.mass_source = type.mass_source;
  c.body = type.shape.body;
  c.outline = type.shape.outline;
  c.studs = type.shape.studs;
  c.pose = pose;
  c.pivots = type.pivots;
  return c;
}

Pose pose_of(const Brick& b) {
  if (b.pose) return *b.pose;
  Pose p;
  p.origin = {kLduPerStud * b.min.x + kLduPerStud * b.size_x() / 2.0,
              -double(kLduPerPlate) * (b.min.y + b.height()),
              kLduPerStud * b.min.z + kLduPerStud * b.size_z() / 2.0};
  if (b.rotated) p.rotation = {0, 0, 1, 0, 1, 0, -1, 0, 0};
  return p;
}

Pose model_pose(const Brick& b) {
  return b.frame ? b.frame->pose.then(pose_of(b)) : pose_of(b);
}

}  // namespace lego
