#include "physics/world_shape.h"

#include <algorithm>
#include <cmath>

namespace lego::physics {
namespace {

double snap(double v) {
  return std::round(v / kSnap) * kSnap;
}

Vec3 to_world(const Pose& pose, const Vec3& local) {
  Vec3 w = lattice_from_ldraw(pose.apply(local));
  for (double& c : w) c = snap(c);
  return w;
}

double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

WorldShape world_shape(const Brick& brick) {
  const Pose pose = pose_of(brick);
  const PartShape& shape = brick.type->shape;
  WorldShape w;
  w.body.reserve(shape.body.size());
  for (const Box& b : shape.body) {
    const Vec3 p = to_world(pose, b.min), q = to_world(pose, b.max);
    Box out;
    for (int a = 0; a < 3; ++a)
      out.min[a] = std::min(p[a], q[a]), out.max[a] = std::max(p[a], q[a]);
    w.body.push_back(out);
  }
  auto place = [&](const std::vector<Connector>& in, std::vector<Connector>& out) {
    out.reserve(in.size());
    for (const Connector& c : in)
      out.push_back({to_world(pose, c.at), lattice_direction(pose.turn(c.direction))});
  };
  place(shape.studs, w.studs);
  place(shape.receptacles, w.receptacles);
  place(shape.bores, w.bores);
  w.shafts.reserve(shape.shafts.size());
  for (const Shaft& s : shape.shafts)
    w.shafts.push_back({s.kind, to_world(pose, s.a), to_world(pose, s.b)});
  if (brick.type->rolls)
    for (const Vec3& p : shape.outline) w.outline.push_back(to_world(pose, p));
  return w;
}

Box OrientedBox::bounds() const {
  Box b;
  for (int r = 0; r < 3; ++r) {
    double extent = 0;
    for (int k = 0; k < 3; ++k) extent += std::abs(axis[k][r]) * half[k];
    b.min[r] = centre[r] - extent;
    b.max[r] = centre[r] + extent;
  }
  return b;
}

OrientedBox as_oriented(const Box& box) {
  OrientedBox o;
  for (int a = 0; a < 3; ++a) {
    o.centre[a] = (box.min[a] + box.max[a]) / 2;
    o.half[a] = (box.max[a] - box.min[a]) / 2;
    o.axis[a] = {0, 0, 0};
    o.axis[a][a] = 1;
  }
  return o;
}

namespace {

std::vector<OrientedBox> oriented_boxes(const Pose& pose, const std::vector<Box>& boxes) {
  std::vector<OrientedBox> out;
  for (const Box& b : boxes) {
    OrientedBox o;
    Vec3 mid{(b.min[0] + b.max[0]) / 2, (b.min[1] + b.max[1]) / 2, (b.min[2] + b.max[2]) / 2};
    o.centre = lattice_from_ldraw(pose.apply(mid));
    for (int k = 0; k < 3; ++k) {
      Vec3 column{pose.rotation[k], pose.rotation[3 + k], pose.rotation[6 + k]};
      const double length = std::sqrt(dot(column, column));
      // A scaled placement scales the box; its axes stay unit vectors.
      o.half[k] = (b.max[k] - b.min[k]) / 2 * length;
      o.axis[k] = lattice_from_ldraw(column);
      if (length > 0)
        for (double& c : o.axis[k]) c /= length;
    }
    out.push_back(o);
  }
  return out;
}

}  // namespace

std::vector<OrientedBox> world_boxes(const CarriedPart& part) {
  return oriented_boxes(part.pose, part.body);
}

std::vector<OrientedBox> world_stud_boxes(const CarriedPart& part, double radius) {
  std::vector<Box> boxes;
  for (const Connector& k : part.studs) boxes.push_back(stud_box(k, radius));
  return oriented_boxes(part.pose, boxes);
}

Box stud_box(const Connector& stud, double radius) {
  Box b{stud.at, stud.at};
  const int ax = axis_of(stud.direction);
  for (int other = 0; other < 3; ++other)
    if (other != ax) b.min[size_t(other)] -= radius, b.max[size_t(other)] += radius;
  (sign_of(stud.direction) > 0 ? b.max : b.min)[size_t(ax)] += 4 * sign_of(stud.direction);
  return b;
}

std::vector<Vec3> world_outline(const CarriedPart& part) {
  std::vector<Vec3> out;
  if (!part.outline.empty()) {
    for (const Vec3& p : part.outline) out.push_back(lattice_from_ldraw(part.pose.apply(p)));
    return out;
  }
  for (const Box& b : part.body)
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{corner & 1 ? b.max[0] : b.min[0], corner & 2 ? b.max[1] : b.min[1],
                   corner & 4 ? b.max[2] : b.min[2]};
      out.push_back(lattice_from_ldraw(part.pose.apply(p)));
    }
  return out;
}

// The flip of y (lattice_from_ldraw) is its own inverse.
Vec3 to_model_direction(const Brick& brick, const Vec3& d) {
  if (!brick.frame) return d;
  return lattice_from_ldraw(brick.frame->pose.rotate(lattice_from_ldraw(d)));
}

Vec3 to_model(const Brick& brick, const Vec3& p) {
  if (!brick.frame) return p;
  return lattice_from_ldraw(brick.frame->pose.apply(lattice_from_ldraw(p)));
}

OrientedBox to_model(const Brick& brick, const Box& box) {
  OrientedBox o = as_oriented(box);
  if (!brick.frame) return o;
  o.centre = to_model(brick, o.centre);
  for (Vec3& axis : o.axis) axis = to_model_direction(brick, axis);
  return o;
}

Box model_bounds(const Brick& brick, const Box& box) {
  return brick.frame ? to_model(brick, box).bounds() : box;
}

bool touch(const OrientedBox& a, const OrientedBox& b, double gap) {
  const Vec3 t{b.centre[0] - a.centre[0], b.centre[1] - a.centre[1], b.centre[2] - a.centre[2]};
  auto separated = [&](const Vec3& axis) {
    const double length = std::sqrt(dot(axis, axis));
    if (length < 1e-9) return false;  // parallel edges: the face axes decide
    double ra = 0, rb = 0;
    for (int k = 0; k < 3; ++k) {
      ra += a.half[k] * std::abs(dot(a.axis[k], axis));
      rb += b.half[k] * std::abs(dot(b.axis[k], axis));
    }
    return std::abs(dot(t, axis)) > ra + rb + gap * length;
  };
  for (int k = 0; k < 3; ++k)
    if (separated(a.axis[k]) || separated(b.axis[k])) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (separated(cross(a.axis[i], b.axis[j]))) return false;
  return true;
}

}  // namespace lego::physics
