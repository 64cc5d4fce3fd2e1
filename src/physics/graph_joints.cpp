// Joints that are not studs (docs/physics.md, "Joints"): Technic pins and axles in holes, hinge
// knuckles and bars in clips, derived from the parts' shafts; and the assumed-rigid joints where
// carried parts, two lattices or two hinge halves tie parts together without a line they share.
#include <algorithm>
#include <cmath>

#include "physics/contact_graph_builder.h"

namespace lego::physics {
namespace {

// A shaft where the assembly puts it.
struct PlacedShaft {
  int brick;
  const Shaft* shaft;
  Vec3 a, b;  // in the model's frame, or in the brick's lattice when `frame` >= 0
  int axis, frame;
};
using Line = std::tuple<int, int64_t, int64_t, int>;  // axis, the line across it, frame

// Lines along the model's axes are compared in the model's frame, so that a hinge half turned on
// its own lattice meets its other half; others within the part's lattice (`frame`).
PlacedShaft place(const Brick& brick, int index, int frame, const Shaft& s) {
  PlacedShaft p{index, &s, to_model(brick, s.a), to_model(brick, s.b), 0, -1};
  int moved = 0;
  for (int k = 0; k < 3; ++k)
    if (std::abs(p.a[size_t(k)] - p.b[size_t(k)]) > 1e-3) ++moved, p.axis = k;
  if (moved != 1)  // turned off the model's axes: compared within its own lattice
    p.a = s.a, p.b = s.b, p.axis = s.axis(), p.frame = frame;
  return p;
}

Line line_of(const PlacedShaft& p, int64_t du, int64_t dv) {
  const int u = (p.axis + 1) % 3, v = (p.axis + 2) % 3;
  return Line{p.axis, std::llround(p.a[size_t(u)]) + du, std::llround(p.a[size_t(v)]) + dv,
              p.frame};
}

// A wheel is drawn by eye onto its pin and into its tyre: there the lines may lie a wheel pin's
// and a hub hole's radius apart, the pin drawn still passing into the hole (the corpus's trucks
// have their wheels 3 to 5 LDU off their pins, touching the ground).
constexpr double kWheelReach = 8;

// The square of side kWheelReach a line crosses: lines within kWheelReach of each other cross
// the same square or neighbouring ones.
Line wheel_cell_of(const PlacedShaft& p, int64_t du, int64_t dv) {
  const int u = (p.axis + 1) % 3, v = (p.axis + 2) % 3;
  return Line{p.axis, int64_t(std::floor(p.a[size_t(u)] / kWheelReach)) + du,
              int64_t(std::floor(p.a[size_t(v)] / kWheelReach)) + dv, p.frame};
}

// Holes, knuckles and clips by the line they lie on; a wheel's hub, rim and tyre by the square
// their line crosses.
struct Receivers {
  std::map<Line, std::vector<PlacedShaft>> by_line, wheels_by_cell;
  void add(const PlacedShaft& p) {
    if (p.shaft->wheel())
      wheels_by_cell[wheel_cell_of(p, 0, 0)].push_back(p);
    else
      by_line[line_of(p, 0, 0)].push_back(p);
  }
};

// How the shafts of one part fit the receivers of another.
struct Fit {
  double lo = 1e300, hi = -1e300;
  bool overlaps = false, holds = false, friction = false;
  int abutting = 0;  // knuckle ends meeting end to end: two when fingers interleave
  const PlacedShaft* on = nullptr;
  Line line{};
};

// Per (part with the hole, part with the shaft): how the shafts `inserted` fit `receivers`,
// within a LDU of the line (a wheel's: kWheelReach) and overlapping along it (knuckles: meeting
// end to end).
std::map<std::pair<int, int>, Fit> shaft_fits(const Receivers& receivers,
                                              const std::vector<PlacedShaft>& inserted,
                                              const std::vector<char>& fixed) {
  std::map<std::pair<int, int>, Fit> fits;
  for (const PlacedShaft& s : inserted)
    for (const bool wheel : {false, true})
      for (int64_t du = -1; du <= 1; ++du)
        for (int64_t dv = -1; dv <= 1; ++dv) {
          const auto& index = wheel ? receivers.wheels_by_cell : receivers.by_line;
          auto it = index.find(wheel ? wheel_cell_of(s, du, dv) : line_of(s, du, dv));
          if (it == index.end()) continue;
          for (const PlacedShaft& r : it->second) {
            const int i = r.brick, j = s.brick;
            if (i == j || (fixed[size_t(i)] && fixed[size_t(j)])) continue;
            if (!Shaft::fits(*s.shaft, *r.shaft) || (s.shaft->knuckle() && i > j)) continue;
            const int axis = s.axis, u = (axis + 1) % 3, v = (axis + 2) % 3;
            if (std::hypot(r.a[size_t(u)] - s.a[size_t(u)], r.a[size_t(v)] - s.a[size_t(v)]) >
                (r.shaft->wheel() ? kWheelReach : kCarriedReach))
              continue;
            const double lo = std::max(std::min(r.a[size_t(axis)], r.b[size_t(axis)]),
                                       std::min(s.a[size_t(axis)], s.b[size_t(axis)]));
            const double hi = std::min(std::max(r.a[size_t(axis)], r.b[size_t(axis)]),
                                       std::max(s.a[size_t(axis)], s.b[size_t(axis)]));
            const bool knuckles = s.shaft->knuckle();
            if (hi - lo < (knuckles ? -kTouch : kMinFace)) continue;
            Fit& f = fits[{i, j}];
            f.lo = std::min(f.lo, lo), f.hi = std::max(f.hi, hi);
            if (hi - lo >= kMinFace)
              f.overlaps = true;
            else
              ++f.abutting;
            const auto kind = s.shaft->kind, other = r.shaft->kind;
            // Two halves joined on two lines cannot turn about either.
            const Line line = line_of(r, 0, 0);
            const bool second_line = f.on && line != f.line;
            f.holds = f.holds || (kind == Shaft::Kind::Axle && other == Shaft::Kind::AxleHole) ||
                      (kind == Shaft::Kind::Rim && other == Shaft::Kind::Tyre) ||
                      (kind == Shaft::Kind::LockingKnuckle && other == kind) ||
                      (knuckles && second_line);
            f.line = line;
            f.friction =
                f.friction || kind == Shaft::Kind::FrictionPin || other == Shaft::Kind::Clip;
            f.on = &r;
          }
        }
  return fits;
}

}  // namespace

// Technic and hinge joints: a pin or an axle of one part on the line of another's hole, within
// a LDU of it and overlapping it, joins the two; so do two hinge halves' knuckles on one line
// that overlap or interleave (fingers between fingers), a bar in a clip, and a wheel's rim in its
// tyre. An axle in an axle hole, a locking hinge and a tyre on its rim hold every way; anything
// else turns about the line (a wheel on its pin or axle), a clip gripping its bar as a friction
// pin does its hole.
void ContactGraphBuilder::join_shafts() {
  Receivers receivers;                // holes, knuckles, clips, hubs and tyres
  std::vector<PlacedShaft> inserted;  // pins, axles, knuckles and bars
  for (int i = 0; i < n_; ++i)
    for (const Shaft& s : shapes_[size_t(i)].shafts) {
      const PlacedShaft p = place(a_.bricks[size_t(i)], i, frame_of(i), s);
      if (s.receives()) receivers.add(p);
      if (!s.receives() || s.knuckle()) inserted.push_back(p);
    }
  for (auto& [pair, f] : shaft_fits(receivers, inserted, g_.fixed)) {
    // Two hinge halves end to end in a row meet at one end; interleaved fingers at two.
    if (!f.overlaps && f.abutting < 2) continue;
    const auto [i, j] = pair;
    Contact c;
    c.lower = g_.fixed[size_t(j)] ? j : i;
    c.upper = g_.fixed[size_t(j)] ? i : j;
    c.joint = true;
    c.joint_kind = f.holds ? Contact::Kind::Holds : Contact::Kind::Turns;
    c.joint_friction = f.friction;
    Vec3 mid = f.on->a, axis{0, 0, 0};
    mid[size_t(f.on->axis)] = (f.lo + f.hi) / 2;
    axis[size_t(f.on->axis)] = 1;
    const Brick& on = a_.bricks[size_t(f.on->brick)];
    c.joint_point = f.on->frame < 0 ? mid : to_model(on, mid);
    c.joint_axis = f.on->frame < 0 ? axis : to_model_direction(on, axis);
    g_.shaft_joints.push_back(add_contact(c));
    shaft_joined_.insert({std::min(i, j), std::max(i, j)});
  }
}

// Assumed-rigid joints, after every other contact: each group ties the bricks it joins along
// the shortest links between their centres (a tree of joints is as rigid as one body). Merged
// into one body, those bricks made rows dense and the interior point method stalled; a star
// from one brick did too. A tree keeps each brick's joints few and their lever arms short.
void ContactGraphBuilder::tie_carried_joints() {
  std::vector<Vec3> centre(static_cast<size_t>(n_));
  for (const CarriedGroup& group : g_.carried_groups) {
    const auto& joins = group.joins;
    if (joins.size() < 2 || !assumed_joints_) continue;
    for (int b : joins) centre[size_t(b)] = body_centre(a_.bricks[size_t(b)]);
    auto distance = [&](int x, int y) {
      double d = 0;
      for (int ax = 0; ax < 3; ++ax)
        d += (centre[size_t(x)][size_t(ax)] - centre[size_t(y)][size_t(ax)]) *
             (centre[size_t(x)][size_t(ax)] - centre[size_t(y)][size_t(ax)]);
      return d;
    };
    // Prim's tree over the joined bricks, from the first.
    std::vector<char> in_tree(joins.size(), 0);
    std::vector<double> best(joins.size(), 1e300);
    std::vector<size_t> link(joins.size(), 0);
    in_tree[0] = 1;
    for (size_t k = 1; k < joins.size(); ++k) best[k] = distance(joins[0], joins[k]);
    for (size_t added = 1; added < joins.size(); ++added) {
      size_t next = 0;
      for (size_t k = 1; k < joins.size(); ++k)
        if (!in_tree[k] && (next == 0 || best[k] < best[next])) next = k;
      in_tree[next] = 1;
      Contact c;
      c.lower = joins[link[next]];
      c.upper = joins[next];
      c.joint = true;
      for (int ax = 0; ax < 3; ++ax)
        c.joint_point[size_t(ax)] =
            (centre[size_t(c.lower)][size_t(ax)] + centre[size_t(c.upper)][size_t(ax)]) / 2;
      add_contact(c);
      for (size_t k = 1; k < joins.size(); ++k)
        if (!in_tree[k] && distance(joins[next], joins[k]) < best[k])
          best[k] = distance(joins[next], joins[k]), link[k] = next;
    }
  }
}

// Where parts of two lattices touch (a turned stand on its base), or two hinge or turntable
// halves touch without a line they share (a hinge whose fingers' primitives are not
// cylinders), nothing tells how they hold: they are joined as a carried part joins what it
// touches (docs/what-it-analyses.md).
void ContactGraphBuilder::join_lattices_and_pivots() {
  auto pivots = [&](int i) { return a_.bricks[size_t(i)].type->pivots; };
  bool any_pivot = false;
  for (int i = 0; i < n_ && !any_pivot; ++i) any_pivot = pivots(i);
  // Legolize's bricks are neither: its many analyses skip this.
  if (assumed_joints_ && (any_turned_ || any_pivot)) {
    std::set<std::pair<int, int>> lattice_pairs, pivot_pairs, snapped;
    if (any_pivot)
      for (const Contact& c : g_.contacts)
        if (c.snap()) snapped.insert({std::min(c.lower, c.upper), std::max(c.lower, c.upper)});
    for (int id = 0; id < int(box_owner_.size()); ++id) {
      const int i = owner(id);
      if (!a_.bricks[size_t(i)].frame && !pivots(i)) continue;
      const OrientedBox o = model_box(id);
      near_in_model(o.bounds(), kCarriedReach, [&](int other) {
        const int j = owner(other);
        const std::pair<int, int> pair{std::min(i, j), std::max(i, j)};
        if (i == j || (g_.fixed[size_t(i)] && g_.fixed[size_t(j)])) return;
        const bool across = frame_of(j) != frame_of(i) && a_.bricks[size_t(i)].frame;
        // Once per pair across lattices: from the turned one when only one is, else from the
        // lower frame id.
        if (across && a_.bricks[size_t(j)].frame && frame_of(j) < frame_of(i)) return;
        // Two halves of one hinge are two parts: the same part side by side in a row is none.
        const bool halves =
            pivots(i) && pivots(j) && a_.bricks[size_t(i)].type != a_.bricks[size_t(j)].type;
        if (!across && !halves) return;
        // Snapped to each other, they hold by their studs; joined, by their joint.
        if (snapped_across_.count(pair) || shaft_joined_.count(pair)) return;
        if (!touch(o, model_box(other), kCarriedReach)) return;
        if (across)
          lattice_pairs.insert(pair);
        else if (!snapped.count(pair))
          pivot_pairs.insert(pair);
      });
    }
    auto join = [&](std::pair<int, int> pair, std::vector<int>& into) {
      const auto [x, y] = pair;
      Contact c;
      // The ground's part, where one is, below: its side has no equations.
      c.lower = g_.fixed[size_t(y)] ? y : x;
      c.upper = g_.fixed[size_t(y)] ? x : y;
      c.joint = true;
      const Vec3 cx = body_centre(a_.bricks[size_t(x)]), cy = body_centre(a_.bricks[size_t(y)]);
      for (int ax = 0; ax < 3; ++ax)
        c.joint_point[size_t(ax)] = (cx[size_t(ax)] + cy[size_t(ax)]) / 2;
      into.push_back(add_contact(c));
    };
    for (const auto& pair : lattice_pairs) join(pair, g_.lattice_joints);
    for (const auto& pair : pivot_pairs) join(pair, g_.pivot_joints);
  }
}

}  // namespace lego::physics
