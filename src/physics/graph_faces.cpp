// Faces that touch, bodies that overlap, and the ground under the parts that reach it.
#include <algorithm>
#include <cmath>

#include "physics/contact_graph_builder.h"

namespace lego::physics {

// Faces that touch, and bodies that overlap.
void ContactGraphBuilder::touch_faces() {
  // A box in several cells is met once per cell: each candidate is taken once (a baseplate near
  // thousands of parts made a search of those seen quadratic).
  std::vector<int> near;
  std::vector<int> met_by(box_owner_.size(), -1);  // per box: the last box that met it
  for (int id = 0; id < int(box_owner_.size()); ++id) {
    const Box& bi = box(id);
    const int i = owner(id);
    if (id == 0 || owner(id - 1) != i) check_time(i);
    near.clear();
    index_.near(bi, kTouch, [&](int other) {
      if (other > id && owner(other) != i && met_by[size_t(other)] != id) {
        met_by[size_t(other)] = id;
        near.push_back(other);
      }
    });
    std::sort(near.begin(), near.end());  // the order meetings have always been made in
    for (const int other : near) {
      const Box& bj = box(other);
      const int j = owner(other);
      if (frame_of(i) != frame_of(j)) continue;
      double overlap[3];
      int touching = -1, shared = 0;
      int wide = 0;
      for (int ax = 0; ax < 3; ++ax) {
        overlap[ax] = std::min(bi.max[ax], bj.max[ax]) - std::max(bi.min[ax], bj.min[ax]);
        if (overlap[ax] > kTouch)
          ++shared;
        else if (overlap[ax] >= -kTouch)
          touching = ax;
        if (overlap[ax] >= kMinFace) ++wide;
      }
      if (shared == 3) {
        g_.overlaps.emplace_back(std::min(i, j), std::max(i, j));
        continue;
      }
      if (shared != 2 || wide != 2 || touching < 0 || (g_.fixed[size_t(i)] && g_.fixed[size_t(j)]))
        continue;
      const bool i_below = std::abs(bi.max[touching] - bj.min[touching]) <= kTouch;
      const int lower = i_below ? i : j, upper = i_below ? j : i;
      const double plane = i_below ? bi.max[touching] : bj.max[touching];
      Box common;
      for (int ax = 0; ax < 3; ++ax) {
        common.min[ax] = std::max(bi.min[ax], bj.min[ax]);
        common.max[ax] = std::min(bi.max[ax], bj.max[ax]);
      }
      Meeting& m = meeting(lower, upper, direction_of(touching, false), plane);
      grow(m.patch, m.has_patch, in_plane(common, touching));
    }
  }
  std::sort(g_.overlaps.begin(), g_.overlaps.end());
  g_.overlaps.erase(std::unique(g_.overlaps.begin(), g_.overlaps.end()), g_.overlaps.end());
}

// A wheel or a tyre stands on the table along a strip under its axle: the points of its outline
// nearest the table, within kTouch of the nearest (a tyre's tread across, a point along). A wide
// patch would let the table hold a turning wheel against its turn.
// `below`: the height of the brick's frame's origin, as stand_on_ground has it.
void ContactGraphBuilder::stand_round_part_on_ground(int i, const std::vector<Vec3>& outline,
                                                     double below) {
  const Brick& brick = a_.bricks[size_t(i)];
  double nearest = 1e300;
  for (const Vec3& p : outline) nearest = std::min(nearest, clearance(to_model(brick, p)));
  if (nearest > kSettleLdu) return;
  Meeting* m = nullptr;
  for (const Vec3& p : outline) {
    const Vec3 q = to_model(brick, p);
    if (clearance(q) > nearest + kTouch) continue;
    if (!m) m = &meeting(kGround, i, kPlusY, table_.at(q[0], q[2]) - below);
    grow(m->patch, m->has_patch, {p[0], p[2], p[0], p[2]});
  }
  widen_to_min_face(m->patch);
  m->support = true;
}

// The ground under the bricks that reach it, or settle onto it. On a lattice turned about the
// vertical the ground lies lower by the height of the lattice's origin; a tilted one stands on
// no ground.
void ContactGraphBuilder::stand_on_ground() {
  for (int i = 0; i < n_; ++i) {
    if (g_.fixed[size_t(i)]) continue;
    const Brick& brick = a_.bricks[size_t(i)];
    double below = 0;  // the frame's origin's height, lattice frame
    if (brick.frame) {
      if (tilted(*brick.frame)) continue;  // its faces are not level: it stands on no ground
      below = to_model(brick, Vec3{0, 0, 0})[1];
    }
    if (const auto& outline = shapes_[size_t(i)].outline; !outline.empty()) {
      stand_round_part_on_ground(i, outline, below);
      continue;
    }
    for (const Box& b : shapes_[size_t(i)].body) {
      // The table's highest point under the box, and how far above it the box's bottom is.
      const Box mb = model_bounds(brick, b);
      double under = -1e300;
      for (double x : {mb.min[0], mb.max[0]})
        for (double z : {mb.min[2], mb.max[2]}) under = std::max(under, table_.at(x, z));
      const double frame_ground = under - below;
      if (b.min[1] <= frame_ground + kSettleLdu) {
        const bool on = std::abs(b.min[1] - frame_ground) <= kTouch;
        Meeting& m = meeting(kGround, i, kPlusY, on ? frame_ground : b.min[1]);
        grow(m.patch, m.has_patch, in_plane(b, 1));
        m.support = true;
      }
    }
  }
  // A turned part's receptacles do not take the baseplate's studs: it rests on them.
  if (g_.ground == GroundMode::Baseplate)
    for (int i = 0; i < n_; ++i)
      if (!g_.fixed[size_t(i)] && !a_.bricks[size_t(i)].frame)
        for (const Connector& r : shapes_[size_t(i)].receptacles)
          if (r.direction == kMinusY && on_ground(r.at[1]))
            meeting(kGround, i, kPlusY, ground_y_).receptacles.push_back(r.at);
}

}  // namespace lego::physics
