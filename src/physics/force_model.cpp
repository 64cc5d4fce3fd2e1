#include "physics/force_model.h"

#include "core/lattice.h"

namespace lego::physics {
namespace {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

Vec3 centre(const Brick& b) {
  return {b.min.x + b.size_x() / 2.0, (b.min.y + b.height() / 2.0) * kStudsPerPlate,
          b.min.z + b.size_z() / 2.0};
}

class Builder {
 public:
  Builder(const Assembly& a, EquilibriumSystem& s) : a_(a), s_(s) {
    for (const Brick& b : a.bricks) centres_.push_back(centre(b));
  }

  // A force `f` (per unit of the column's value) applied to `brick` at point `p`.
  void apply(int brick, Vec3 p, Vec3 f) {
    if (brick == kGround) return;  // the ground has no equations
    const Vec3& c = centres_[brick];
    const Vec3 r{p.x - c.x, p.y - c.y, p.z - c.z};
    const double entries[6] = {
        f.x, f.y, f.z, r.y * f.z - r.z * f.y, r.z * f.x - r.x * f.z, r.x * f.y - r.y * f.x};
    for (int e = 0; e < 6; ++e)
      if (entries[e] != 0) {
        s_.row_index.push_back(EquilibriumSystem::row(brick, e));
        s_.value.push_back(entries[e]);
      }
  }
  void end_column(ForceKind kind, int contact) {
    s_.kind.push_back(kind);
    s_.contact.push_back(contact);
    s_.column_start.push_back(int(s_.row_index.size()));
  }

 private:
  const Assembly& a_;
  EquilibriumSystem& s_;
  std::vector<Vec3> centres_;
};

}  // namespace

EquilibriumSystem build_equilibrium(const Assembly& a, const ContactGraph& g) {
  EquilibriumSystem s;
  const int n = int(a.bricks.size());
  s.rows = 6 * n;
  s.row_index.reserve(6 * g.friction_points.size() + 24 * g.stacked.size() + 16 * g.sides.size());
  s.value.reserve(s.row_index.capacity());
  Builder b(a, s);

  // Friction: pulls the upper brick down and the lower one up, at the knob rim.
  for (int ci = 0; ci < int(g.stacked.size()); ++ci) {
    const auto& c = g.stacked[ci];
    const double y = c.y * kStudsPerPlate;
    for (uint32_t k = 0; k < c.point_count; ++k) {
      const FrictionPoint& p = g.friction_points[c.first_point + k];
      b.apply(c.upper, {p.x, y, p.z}, {0, -1, 0});
      b.apply(c.lower, {p.x, y, p.z}, {0, 1, 0});
      b.end_column(ForceKind::Friction, ci);
    }
  }
  s.friction_columns = s.columns();

  for (int ci = 0; ci < int(g.stacked.size()); ++ci) {
    const auto& c = g.stacked[ci];
    const double y = c.y * kStudsPerPlate;
    // Normal forces at the corners of the overlap push the two bricks apart.
    for (int corner = 0; corner < 4; ++corner) {
      Vec3 p{double(corner & 1 ? c.overlap.x1 : c.overlap.x0), y,
             double(corner & 2 ? c.overlap.z1 : c.overlap.z0)};
      b.apply(c.upper, p, {0, 1, 0});
      b.apply(c.lower, p, {0, -1, 0});
      b.end_column(ForceKind::Normal, ci);
    }
    // The horizontal support force of the knobs, where there are knobs or a ground to lean on.
    if (c.snap() || c.lower == kGround) {
      Vec3 mid{(c.overlap.x0 + c.overlap.x1) / 2.0, y, (c.overlap.z0 + c.overlap.z1) / 2.0};
      for (Vec3 dir : {Vec3{1, 0, 0}, Vec3{0, 0, 1}}) {
        b.apply(c.upper, mid, dir);
        b.apply(c.lower, mid, {-dir.x, 0, -dir.z});
        b.end_column(ForceKind::Support, ci);
      }
    }
  }

  for (int si = 0; si < int(g.sides.size()); ++si) {
    const auto& sc = g.sides[si];
    for (int corner = 0; corner < 4; ++corner) {
      double y = (corner & 1 ? sc.y1 : sc.y0) * kStudsPerPlate;
      double t = corner & 2 ? sc.t1 : sc.t0;
      Vec3 p = sc.axis == 0 ? Vec3{double(sc.plane), y, t} : Vec3{t, y, double(sc.plane)};
      Vec3 push = sc.axis == 0 ? Vec3{1, 0, 0} : Vec3{0, 0, 1};
      b.apply(sc.positive, p, push);
      b.apply(sc.negative, p, {-push.x, 0, -push.z});
      b.end_column(ForceKind::Normal, -1 - si);
    }
  }

  // b: gravity at each brick's centre, and external loads, moved to the right-hand side.
  s.rhs.assign(s.rows, 0.0);
  for (int i = 0; i < n; ++i) s.rhs[EquilibriumSystem::row(i, 1)] = a.bricks[i].mass_g() * kGravity;
  for (const ExternalLoad& load : a.loads) {
    if (load.brick < 0 || load.brick >= n) continue;
    const Brick& br = a.bricks[load.brick];
    const Vec3 c = centre(br);
    const Vec3 f{load.force_n[0] * 1e3, load.force_n[1] * 1e3,
                 load.force_n[2] * 1e3};  // N -> g·m/s²
    std::vector<Vec3> points;
    if (load.spread_over_top_knobs) {
      for (int x = br.min.x; x < br.max_x(); ++x)
        for (int z = br.min.z; z < br.max_z(); ++z)
          points.push_back({x + 0.5, br.top() * kStudsPerPlate, z + 0.5});
    } else {
      points.push_back({load.point[0], load.point[1] * kStudsPerPlate, load.point[2]});
    }
    const double share = 1.0 / double(points.size());
    for (const Vec3& p : points) {
      const Vec3 r{p.x - c.x, p.y - c.y, p.z - c.z};
      const Vec3 fp{f.x * share, f.y * share, f.z * share};
      const double wrench[6] = {fp.x,
                                fp.y,
                                fp.z,
                                r.y * fp.z - r.z * fp.y,
                                r.z * fp.x - r.x * fp.z,
                                r.x * fp.y - r.y * fp.x};
      for (int e = 0; e < 6; ++e) s.rhs[EquilibriumSystem::row(load.brick, e)] -= wrench[e];
    }
  }
  return s;
}

}  // namespace lego::physics
