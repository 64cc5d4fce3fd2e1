#include "core/part_shape.h"

#include <algorithm>

#include "core/lattice.h"

namespace lego {

Box PartShape::bounds() const {
  if (body.empty()) return {};
  Box out = body.front();
  for (const Box& b : body)
    for (int a = 0; a < 3; ++a) {
      out.min[a] = std::min(out.min[a], b.min[a]);
      out.max[a] = std::max(out.max[a], b.max[a]);
    }
  return out;
}

double PartShape::body_volume() const {
  double v = 0;
  for (const Box& b : body) v += b.volume();
  return v;
}

PartShape box_brick_shape(int length, int width, int height, bool studs) {
  PartShape s;
  const double hx = kLduPerStud * length / 2.0, hz = kLduPerStud * width / 2.0;
  const double bottom = double(kLduPerPlate * height);
  s.body.push_back({{-hx, 0, -hz}, {hx, bottom, hz}});
  for (int i = 0; i < length; ++i)
    for (int k = 0; k < width; ++k) {
      const double x = -hx + kLduPerStud * (i + 0.5), z = -hz + kLduPerStud * (k + 0.5);
      if (studs) s.studs.push_back({{x, 0, z}, kMinusY});
      s.receptacles.push_back({{x, bottom, z}, kPlusY});
      if (i > 0 && k > 0)
        s.bores.push_back({{x - kLduPerStud / 2.0, bottom, z - kLduPerStud / 2.0}, kPlusY});
    }
  return s;
}

}  // namespace lego
