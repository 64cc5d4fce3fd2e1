#include "physics/contact_graph.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace lego::physics {
namespace {

// Cell -> brick occupancy, the spatial index that keeps contact search linear.
class Occupancy {
 public:
  explicit Occupancy(size_t cells) { map_.reserve(cells); }
  static uint64_t key(int x, int y, int z) {
    constexpr int64_t kOffset = 1 << 20;
    return (uint64_t(x + kOffset) << 42) | (uint64_t(y + kOffset) << 21) | uint64_t(z + kOffset);
  }
  // Returns the brick already in the cell, or -1 after claiming it for `brick`.
  int claim(int x, int y, int z, int brick) {
    auto [it, inserted] = map_.try_emplace(key(x, y, z), brick);
    return inserted ? -1 : it->second;
  }
  int at(int x, int y, int z) const {
    auto it = map_.find(key(x, y, z));
    return it == map_.end() ? -1 : it->second;
  }

 private:
  std::unordered_map<uint64_t, int> map_;
};

// Friction points of one knob (its cell's minimum corner at cx, cz) inside the cavity of `upper`.
void add_knob_points(const Brick& upper, int cx, int cz, std::vector<FrictionPoint>& out) {
  auto inside = [&](int x, int z) {
    return x >= upper.min.x && x < upper.max_x() && z >= upper.min.z && z < upper.max_z();
  };
  const bool one_wide = upper.size_x() == 1 || upper.size_z() == 1;
  const double ox = cx + 0.5, oz = cz + 0.5, r = kKnobRimRadius,
               d = kKnobRimRadius / std::sqrt(2.0);
  static constexpr int kAxis[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& a : kAxis) {
    // A wall where the cavity ends; in a one-stud-wide brick also the pins between knobs.
    if (one_wide || !inside(cx + a[0], cz + a[1])) out.push_back({ox + r * a[0], oz + r * a[1]});
  }
  if (one_wide) return;
  static constexpr int kDiagonal[4][2] = {{1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  for (const auto& g : kDiagonal) {
    // A tube sits between four knobs: where the three neighbouring cells are all cavity.
    if (inside(cx + g[0], cz) && inside(cx, cz + g[1]) && inside(cx + g[0], cz + g[1]))
      out.push_back({ox + d * g[0], oz + d * g[1]});
  }
}

void add_stacked(ContactGraph& g, const Assembly& a, int lower, int upper, bool knobs_engage) {
  const Brick& u = a.bricks[upper];
  StackedContact c;
  c.lower = lower;
  c.upper = upper;
  c.y = u.min.y;
  if (lower == kGround) {
    c.overlap = {u.min.x, u.min.z, u.max_x(), u.max_z()};
  } else {
    const Brick& l = a.bricks[lower];
    c.overlap = {std::max(u.min.x, l.min.x), std::max(u.min.z, l.min.z),
                 std::min(u.max_x(), l.max_x()), std::min(u.max_z(), l.max_z())};
  }
  c.first_point = uint32_t(g.friction_points.size());
  if (knobs_engage) {
    c.knobs = c.overlap.area();
    for (int x = c.overlap.x0; x < c.overlap.x1; ++x)
      for (int z = c.overlap.z0; z < c.overlap.z1; ++z) add_knob_points(u, x, z, g.friction_points);
  }
  c.point_count = uint32_t(g.friction_points.size()) - c.first_point;
  g.contacts_of[upper].push_back(int(g.stacked.size()));
  if (lower != kGround) g.contacts_of[lower].push_back(int(g.stacked.size()));
  g.stacked.push_back(c);
}

}  // namespace

ContactGraph ContactGraph::build(const Assembly& a, GroundMode ground) {
  ContactGraph g;
  g.ground = ground;
  g.ground_y = a.ground_level();
  const int n = int(a.bricks.size());
  g.contacts_of.resize(n);
  size_t cells = 0;
  for (const Brick& b : a.bricks) cells += size_t(b.size_x()) * b.size_z() * b.height();
  Occupancy occupancy(cells);
  std::vector<std::pair<int, int>> overlaps;
  for (int i = 0; i < n; ++i) {
    const Brick& b = a.bricks[i];
    for (int y = b.min.y; y < b.top(); ++y)
      for (int x = b.min.x; x < b.max_x(); ++x)
        for (int z = b.min.z; z < b.max_z(); ++z)
          if (int other = occupancy.claim(x, y, z, i); other >= 0) overlaps.emplace_back(other, i);
  }
  std::sort(overlaps.begin(), overlaps.end());
  overlaps.erase(std::unique(overlaps.begin(), overlaps.end()), overlaps.end());
  g.overlaps = std::move(overlaps);

  std::vector<int> seen;  // neighbours already paired with the current brick
  for (int i = 0; i < n; ++i) {
    const Brick& u = a.bricks[i];
    // Stacked contacts: what lies right under the bottom face.
    if (u.min.y == g.ground_y) {
      add_stacked(g, a, kGround, i, ground == GroundMode::Baseplate);
    } else {
      seen.clear();
      for (int x = u.min.x; x < u.max_x(); ++x)
        for (int z = u.min.z; z < u.max_z(); ++z) {
          int l = occupancy.at(x, u.min.y - 1, z);
          if (l < 0 || l == i || std::find(seen.begin(), seen.end(), l) != seen.end()) continue;
          seen.push_back(l);
          if (a.bricks[l].top() == u.min.y) add_stacked(g, a, l, i, a.bricks[l].type->has_knobs);
        }
    }
    // Side contacts across the +x and +z faces.
    for (int axis : {0, 2}) {
      seen.clear();
      const int plane = axis == 0 ? u.max_x() : u.max_z();
      const int t_lo = axis == 0 ? u.min.z : u.min.x, t_hi = axis == 0 ? u.max_z() : u.max_x();
      for (int y = u.min.y; y < u.top(); ++y)
        for (int t = t_lo; t < t_hi; ++t) {
          int o = axis == 0 ? occupancy.at(plane, y, t) : occupancy.at(t, y, plane);
          if (o < 0 || o == i || std::find(seen.begin(), seen.end(), o) != seen.end()) continue;
          seen.push_back(o);
          const Brick& v = a.bricks[o];
          if ((axis == 0 ? v.min.x : v.min.z) != plane) continue;  // overlapping, not touching
          SideContact s;
          s.negative = i;
          s.positive = o;
          s.axis = axis;
          s.plane = plane;
          s.y0 = std::max(u.min.y, v.min.y);
          s.y1 = std::min(u.top(), v.top());
          s.t0 = std::max(t_lo, axis == 0 ? v.min.z : v.min.x);
          s.t1 = std::min(t_hi, axis == 0 ? v.max_z() : v.max_x());
          g.sides.push_back(s);
        }
    }
  }
  return g;
}

}  // namespace lego::physics
