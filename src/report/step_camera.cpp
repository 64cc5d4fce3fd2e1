#include "report/step_camera.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/brick_catalog.h"

namespace lego::report {

namespace {

constexpr double kPi = 3.14159265358979323846;
// LeoCAD's camera: its vertical field of view (degrees); the booklet's direction of view.
constexpr double kFov = 30, kLatitude = 30, kLongitude = 45;
constexpr double kMargin = 0.9;   // the sphere is wider than the model it holds seen from any side
constexpr double kSmallest = 30;  // LDU: a frame never closer than this around one small part
constexpr double kNewShare = 1 / 3.0;  // new parts smaller than this share of the model: framed

using Point = std::array<double, 3>;

// LeoCAD keeps its cameras in its own frame: z up, LDraw's z as y.
Point leocad(const Point& p) {
  return {p[0], p[2], -p[1]};
}

}  // namespace

void FrameBox::add(const Point& p) {
  for (int k = 0; k < 3; ++k) {
    min[size_t(k)] = std::min(min[size_t(k)], p[size_t(k)]);
    max[size_t(k)] = std::max(max[size_t(k)], p[size_t(k)]);
  }
}

void FrameBox::add(const FrameBox& b) {
  if (b.empty()) return;
  add(b.min);
  add(b.max);
}

Point FrameBox::centre() const {
  return {(min[0] + max[0]) / 2, (min[1] + max[1]) / 2, (min[2] + max[2]) / 2};
}

double FrameBox::radius() const {
  return empty() ? 0 : std::hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]) / 2;
}

FrameBox part_box(const ldraw::PlacedPart& part, const std::optional<Box>& body) {
  // Local corners: a catalog part's body from its top (LDraw's origin of a brick) down; any other
  // part two studs around its origin, which is inside most parts.
  Point lo{-20, -20, -20}, hi{20, 20, 20};
  if (body) {
    lo = body->min;
    hi = body->max;
  } else if (const BrickType* t = BrickCatalog::standard().find(part.part)) {
    lo = {-10.0 * t->length, 0, -10.0 * t->width};
    hi = {10.0 * t->length, 8.0 * t->height, 10.0 * t->width};
  }
  FrameBox box;
  for (int corner = 0; corner < 8; ++corner) {
    const Point local{corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1],
                      corner & 4 ? hi[2] : lo[2]};
    Point world = part.transform.pos;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        world[size_t(r)] += part.transform.rot[size_t(3 * r + k)] * local[size_t(k)];
    box.add(world);
  }
  return box;
}

Frame frame_step(const FrameBox& new_parts, const FrameBox& so_far) {
  Frame f{so_far.centre(), so_far.radius()};
  if (!new_parts.empty() && new_parts.radius() < kNewShare * so_far.radius())
    f = {new_parts.centre(), kNewShare * so_far.radius()};
  f.radius = std::max(f.radius, kSmallest);
  return f;
}

std::string camera_lines(const std::string& name, const std::vector<Frame>& frames) {
  const double lat = kLatitude * kPi / 180, lon = kLongitude * kPi / 180;
  // From the target towards the camera, in LDraw's frame: up (-y), and to +x and -z, as LeoCAD's
  // --camera-angles 30 45 sees the cover.
  const Point towards{std::cos(lat) * std::sin(lon), -std::sin(lat),
                      -std::cos(lat) * std::cos(lon)};
  const Point up = leocad({0, -1, 0});
  std::string position, target, upward;
  for (size_t k = 0; k < frames.size(); ++k) {
    const Frame& f = frames[k];
    const double distance = kMargin * f.radius / std::sin(kFov / 2 * kPi / 180);
    Point eye;
    for (size_t i = 0; i < 3; ++i) eye[i] = f.centre[i] + distance * towards[i];
    const Point e = leocad(eye), t = leocad(f.centre);
    position += fmt::format("0 !LEOCAD CAMERA POSITION_KEY {} {:.3f} {:.3f} {:.3f}\n", k + 1, e[0],
                            e[1], e[2]);
    target += fmt::format("0 !LEOCAD CAMERA TARGET_POSITION_KEY {} {:.3f} {:.3f} {:.3f}\n", k + 1,
                          t[0], t[1], t[2]);
    upward +=
        fmt::format("0 !LEOCAD CAMERA UP_VECTOR_KEY {} {} {} {}\n", k + 1, up[0], up[1], up[2]);
  }
  return fmt::format(
      "0 !LEOCAD CAMERA FOV {} ZNEAR 10 ZFAR 100000\n{}{}{}0 !LEOCAD CAMERA NAME {}\n", kFov,
      position, target, upward, name);
}

}  // namespace lego::report
