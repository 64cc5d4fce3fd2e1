#include "layout/where_on_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <climits>

namespace lego::layout {

namespace {

// A brick's place along one axis of its layer: against one edge, against both (it spans the
// layer), or some studs in from the nearer edge.
struct Along {
  bool spans = false;
  const char* edge = "";  // the nearer edge
  int in = 0;             // studs between it and that edge
};

Along along(int lo, int hi, int brick_lo, int brick_hi, const char* low_edge,
            const char* high_edge) {
  const int from_low = brick_lo - lo, from_high = hi - brick_hi;
  if (from_low == 0 && from_high == 0) return {true, "", 0};
  return from_low <= from_high ? Along{false, low_edge, from_low}
                               : Along{false, high_edge, from_high};
}

std::string studs_in(const Along& a) {
  return fmt::format("{} stud{} in from the {}", a.in, a.in == 1 ? "" : "s", a.edge);
}

}  // namespace

std::string where_on_model(const Assembly& assembly, int brick) {
  const Brick& b = assembly.bricks[size_t(brick)];
  int bottom = INT_MAX;
  int x_lo = INT_MAX, x_hi = INT_MIN, z_lo = INT_MAX, z_hi = INT_MIN;
  for (const Brick& o : assembly.bricks) {
    bottom = std::min(bottom, o.min.y);
    if (o.min.y != b.min.y) continue;
    x_lo = std::min(x_lo, o.min.x);
    x_hi = std::max(x_hi, o.max_x());
    z_lo = std::min(z_lo, o.min.z);
    z_hi = std::max(z_hi, o.max_z());
  }
  const std::string layer = fmt::format("layer {}", (b.min.y - bottom) / kPlatesPerBrick + 1);
  const Along x = along(x_lo, x_hi, b.min.x, b.max_x(), "left", "right");
  const Along z = along(z_lo, z_hi, b.min.z, b.max_z(), "front", "back");
  if (x.spans && z.spans) return "filling " + layer;
  if (x.spans)
    return z.in == 0 ? fmt::format("along the whole {} edge of {}", z.edge, layer)
                     : fmt::format("across {} from left to right, {}", layer, studs_in(z));
  if (z.spans)
    return x.in == 0 ? fmt::format("along the whole {} edge of {}", x.edge, layer)
                     : fmt::format("across {} from front to back, {}", layer, studs_in(x));
  if (x.in == 0 && z.in == 0)
    return fmt::format("at the {} {} corner of {}", z.edge, x.edge, layer);
  if (z.in == 0) return fmt::format("on the {} edge of {}, {}", z.edge, layer, studs_in(x));
  if (x.in == 0) return fmt::format("on the {} edge of {}, {}", x.edge, layer, studs_in(z));
  return fmt::format("in {}, {} and {} from the {}", layer, studs_in(x), z.in, z.edge);
}

}  // namespace lego::layout
