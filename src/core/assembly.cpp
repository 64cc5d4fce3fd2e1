#include "core/assembly.h"

#include <cmath>

namespace lego {

int Pose::turn(int direction) const {
  const int a = axis_of(direction);
  for (int r = 0; r < 3; ++r) {
    const double m = rotation[3 * r + a];
    if (std::abs(m) > 0.5) return direction_of(r, (m < 0) != (sign_of(direction) < 0));
  }
  return direction;
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

}  // namespace lego
