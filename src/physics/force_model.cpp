#include "physics/force_model.h"

#include <array>
#include <cmath>

#include "core/lattice.h"
#include "physics/world_shape.h"

namespace lego::physics {
namespace {

// Coefficients are forces (1) and lever arms in studs (1e-2 and up): below this is roundoff.
constexpr double kNegligible = 1e-9;

Vec3 studs(const Vec3& ldu) {
  return {ldu[0] / kLduPerStud, ldu[1] / kLduPerStud, ldu[2] / kLduPerStud};
}

Vec3 unit(int axis, double sign = 1) {
  Vec3 v{0, 0, 0};
  v[size_t(axis)] = sign;
  return v;
}

class Builder {
 public:
  Builder(EquilibriumSystem& s, std::vector<Vec3> centres) : s_(s), centres_(std::move(centres)) {}

  // A force `f` (per unit of the column's value) applied to `brick` at point `p` (studs).
  void apply(int brick, const Vec3& p, const Vec3& f) {
    if (brick == kGround) return;  // the ground has no equations
    const int body = s_.body_of[size_t(brick)];
    if (body < 0) return;  // nor have fixed bricks
    const auto entries = wrench(body, p, f);
    // Lever arms are differences of coordinates that carry roundoff (a centre averaged over
    // boxes): a 1e-16 entry is a zero, and kept it makes its row nearly empty, not empty,
    // which the interior point method cannot tell from a real equation.
    for (int e = 0; e < 6; ++e)
      if (std::abs(entries[size_t(e)]) > kNegligible) {
        s_.row_index.push_back(EquilibriumSystem::row(body, e));
        s_.value.push_back(entries[size_t(e)]);
      }
  }
  // A moment `m` (per unit of the column's value) on `brick`.
  void apply_moment(int brick, const Vec3& m) {
    if (brick == kGround || s_.body_of[size_t(brick)] < 0) return;
    for (int e = 0; e < 3; ++e)
      if (m[size_t(e)] != 0) {
        s_.row_index.push_back(EquilibriumSystem::row(s_.body_of[size_t(brick)], 3 + e));
        s_.value.push_back(m[size_t(e)]);
      }
  }
  void end_column(ForceKind kind, int contact) {
    s_.kind.push_back(kind);
    s_.contact.push_back(contact);
    s_.column_start.push_back(int(s_.row_index.size()));
  }
  // A fixed force on a body, moved to the right-hand side.
  void load(int body, const Vec3& p, const Vec3& f) {
    const auto w = wrench(body, p, f);
    const double size = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    load_size_.resize(s_.rhs.size(), 0.0);
    for (int e = 0; e < 6; ++e) {
      const size_t row = size_t(EquilibriumSystem::row(body, e));
      s_.rhs[row] -= w[size_t(e)];
      load_size_[row] += size;
    }
  }
  // The loads' moments have lever arms with the same roundoff as the columns', and loads may
  // cancel: a row left with less than kNegligible (studs) times the forces loaded on its body
  // has no load. Kept, it is an equation no force can meet where it has no variables (the
  // corpus's tan mosque: a moment of 1.3e-15 on a plate's row without columns made the model
  // "need" friction a million times T).
  void drop_roundoff_loads() {
    for (size_t row = 0; row < load_size_.size(); ++row)
      if (std::abs(s_.rhs[row]) <= kNegligible * load_size_[row]) s_.rhs[row] = 0;
  }

 private:
  EquilibriumSystem& s_;
  std::vector<Vec3> centres_;
  std::vector<double> load_size_;  // per row: the sum of |load| put on it

  // Force and moment about the body's centre of `f` applied at `p`.
  std::array<double, 6> wrench(int body, const Vec3& p, const Vec3& f) const {
    const Vec3& c = centres_[size_t(body)];
    const Vec3 r{p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    return {f[0],
            f[1],
            f[2],
            r[1] * f[2] - r[2] * f[1],
            r[2] * f[0] - r[0] * f[2],
            r[0] * f[1] - r[1] * f[0]};
  }
};

// The axes a joint holds a moment about (unit vectors, the model's frame): all three, or for a
// joint that turns the two across its axis.
std::vector<Vec3> moment_axes(const Contact& c) {
  if (c.joint_kind != Contact::Kind::Turns) return {unit(0), unit(1), unit(2)};
  const Vec3& w = c.joint_axis;
  std::vector<Vec3> out;
  for (int a = 0; a < 3; ++a)  // the lattice axes across it, where it lies along one
    if (std::abs(w[size_t(a)]) < kNegligible) out.push_back(unit(a));
  if (out.size() == 2) return out;
  // Otherwise two unit vectors across it: the lattice axis least along it, made square to it,
  // and their cross product.
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(w[size_t(a)]) < std::abs(w[size_t(least)])) least = a;
  Vec3 u = unit(least);
  const double along = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
  for (int k = 0; k < 3; ++k) u[size_t(k)] -= along * w[size_t(k)];
  const double length = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& x : u) x /= length;
  const Vec3 v{w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0]};
  return {u, v};
}

// A contact's points and directions in the model's frame (studs), where it is turned.
Vec3 point_of(const Assembly& a, const Contact& c, const Vec3& ldu) {
  return studs(c.turned ? to_model(a.bricks[size_t(c.upper)], ldu) : ldu);
}
Vec3 model_direction(const Assembly& a, const Contact& c, const Vec3& d) {
  return c.turned ? to_model_direction(a.bricks[size_t(c.upper)], d) : d;
}

void add_friction_columns(const Assembly& a, const ContactGraph& g, const std::vector<char>& taken,
                          const Formulation& model, Builder& b) {
  // Friction pulls the upper part towards the lower one, at the knob rim. A column's value is
  // the force over the point's share of T (knob_grip.h), so that every friction column is
  // bounded by T alike: the LP's C_M is T less the largest of those values. A friction pin's
  // grip is such a column each way, its moment about the pin kFrictionPinMoment at T.
  for (int ci = 0; ci < int(g.contacts.size()); ++ci) {
    if (!taken[size_t(ci)]) continue;
    const Contact& c = g.contacts[size_t(ci)];
    if (c.joint && c.joint_kind == Contact::Kind::Turns && c.joint_friction &&
        !model.turning_joints_hold) {
      for (double sign : {1.0, -1.0}) {
        const double m = sign * kFrictionPinMoment / kMaxFrictionLoad;
        const Vec3 e{c.joint_axis[0] * m, c.joint_axis[1] * m, c.joint_axis[2] * m};
        b.apply_moment(c.upper, e);
        b.apply_moment(c.lower, {-e[0], -e[1], -e[2]});
        b.end_column(ForceKind::Friction, ci);
      }
      continue;
    }
    const Vec3 d = model_direction(a, c, unit(axis_of(c.direction), sign_of(c.direction)));
    for (uint32_t k = 0; k < c.point_count; ++k) {
      const FrictionPoint& p = g.friction_points[c.first_point + k];
      const Vec3 at = point_of(a, c, {p.x, p.y, p.z});
      const double share = model.knob_balance ? p.share : 1;
      b.apply(c.upper, at, {-d[0] * share, -d[1] * share, -d[2] * share});
      b.apply(c.lower, at, {d[0] * share, d[1] * share, d[2] * share});
      b.end_column(ForceKind::Friction, ci);
    }
  }
}

// Pushes (normal forces) and the knobs' support forces and twists; a joint's free force and
// moments.
void add_push_and_support_columns(const Assembly& a, const ContactGraph& g,
                                  const std::vector<char>& taken, const Formulation& model,
                                  EquilibriumSystem& s, Builder& b) {
  for (int ci = 0; ci < int(g.contacts.size()); ++ci) {
    if (!taken[size_t(ci)]) continue;
    const Contact& c = g.contacts[size_t(ci)];
    if (c.joint) {  // any force and moment, both ways: free columns, like the support forces
      const Vec3 at = studs(c.joint_point);
      for (int a = 0; a < 3; ++a) {
        const Vec3 e = unit(a, kJointUnit);
        b.apply(c.upper, at, e);
        b.apply(c.lower, at, {-e[0], -e[1], -e[2]});
        b.end_column(ForceKind::Support, ci);
      }
      // A joint that turns holds no moment about its axis (its friction is taken as none).
      for (const Vec3& m : moment_axes(c)) {
        const Vec3 e{m[0] * kJointUnit, m[1] * kJointUnit, m[2] * kJointUnit};
        b.apply_moment(c.upper, e);
        b.apply_moment(c.lower, {-e[0], -e[1], -e[2]});
        b.end_column(ForceKind::Support, ci);
      }
      if (c.joint_kind == Contact::Kind::Turns && model.turning_joints_hold) {
        const Vec3& m = c.joint_axis;
        const Vec3 e{m[0] * kJointUnit, m[1] * kJointUnit, m[2] * kJointUnit};
        b.apply_moment(c.upper, e);
        b.apply_moment(c.lower, {-e[0], -e[1], -e[2]});
        s.turning_columns.push_back(s.columns());
        b.end_column(ForceKind::Support, ci);
      }
      continue;
    }
    const int axis = axis_of(c.direction), f = kInPlane[axis][0], sd = kInPlane[axis][1];
    const Vec3 d = model_direction(a, c, unit(axis, sign_of(c.direction)));
    auto point = [&](double pf, double ps) {
      Vec3 p{0, 0, 0};
      p[size_t(axis)] = c.plane;
      p[size_t(f)] = pf;
      p[size_t(sd)] = ps;
      return point_of(a, c, p);
    };
    // Normal forces at the corners of the patch push the two parts apart (or, to be measured
    // against that, at the knobs' contacts).
    if (model.push_at_knobs && c.point_count > 0) {
      for (uint32_t k = 0; k < c.point_count; ++k) {
        const FrictionPoint& p = g.friction_points[c.first_point + k];
        const Vec3 at = point_of(a, c, {p.x, p.y, p.z});
        b.apply(c.upper, at, d);
        b.apply(c.lower, at, {-d[0], -d[1], -d[2]});
        b.end_column(ForceKind::Normal, ci);
      }
    } else {
      for (int corner = 0; corner < 4; ++corner) {
        const Vec3 p =
            point(corner & 1 ? c.patch.u1 : c.patch.u0, corner & 2 ? c.patch.v1 : c.patch.v0);
        b.apply(c.upper, p, d);
        b.apply(c.lower, p, {-d[0], -d[1], -d[2]});
        b.end_column(ForceKind::Normal, ci);
      }
    }
    // The support force of the knobs in the plane, where there are knobs or a ground to lean on.
    if (c.support) {
      const Vec3 mid = point((c.patch.u0 + c.patch.u1) / 2, (c.patch.v0 + c.patch.v1) / 2);
      for (int in_plane : {f, sd}) {
        const Vec3 e = model_direction(a, c, unit(in_plane));
        b.apply(c.upper, mid, e);
        b.apply(c.lower, mid, {-e[0], -e[1], -e[2]});
        b.end_column(ForceKind::Support, ci);
      }
      // Two knobs or more, pressing sideways in their receptacles, also hold a twist about the
      // knobs' axis, as the support force holds the push across it (knobs do not break); one
      // knob turns in its receptacle.
      if (c.studs >= 2 && model.knobs_hold_twist) {
        const Vec3 e = model_direction(a, c, unit(axis, kJointUnit));
        b.apply_moment(c.upper, e);
        b.apply_moment(c.lower, {-e[0], -e[1], -e[2]});
        b.end_column(ForceKind::Support, ci);
      }
    }
  }
}

// b: gravity at each brick's centre and each carried part's, and external loads.
void add_loads(const Assembly& a, const ContactGraph& g, const EquilibriumSystem& s,
               const std::vector<Vec3>& brick_centre, Builder& b) {
  const int n = int(a.bricks.size());
  for (int i = 0; i < n; ++i)
    if (const int body = s.body_of[size_t(i)]; body >= 0)
      b.load(body, brick_centre[size_t(i)], {0, -a.bricks[size_t(i)].mass_g() * kGravity, 0});
  for (const CarriedGroup& group : g.carried_groups) {
    if (group.bearer < 0) continue;
    const int body = s.body_of[size_t(group.bearer)];
    if (body >= 0) b.load(body, studs(group.centre), {0, -group.mass_g * kGravity, 0});
  }
  for (const ExternalLoad& load : a.loads) {
    if (load.brick < 0 || load.brick >= n) continue;
    const int body = s.body_of[size_t(load.brick)];
    if (body < 0) continue;
    const Vec3 f{load.force_n[0] * 1e3, load.force_n[1] * 1e3, load.force_n[2] * 1e3};  // N -> mN
    std::vector<Vec3> points;
    if (load.spread_over_top_knobs) {
      const Brick& brick = a.bricks[size_t(load.brick)];
      const WorldShape w = world_shape(brick);
      for (const Connector& k : w.studs)
        if (k.direction == kPlusY) points.push_back(studs(to_model(brick, k.at)));
      if (points.empty()) {  // no knob on top: the middle of its top face
        Box top = w.body.front();
        for (const Box& bx : w.body)
          if (bx.max[1] > top.max[1]) top = bx;
        points.push_back(studs(to_model(brick, Vec3{(top.min[0] + top.max[0]) / 2, top.max[1],
                                                    (top.min[2] + top.max[2]) / 2})));
      }
    } else {
      points.push_back({load.point[0], load.point[1] * kStudsPerPlate, load.point[2]});
    }
    const double share = 1.0 / double(points.size());
    for (const Vec3& p : points) b.load(body, p, {f[0] * share, f[1] * share, f[2] * share});
  }
}

}  // namespace

std::vector<double> EquilibriumSystem::unbalanced(const std::vector<double>& forces) const {
  std::vector<double> left = rhs;
  for (int j = 0; j < columns(); ++j)
    if (const double f = forces[size_t(j)]; f != 0)
      for (int e = column_start[size_t(j)]; e < column_start[size_t(j) + 1]; ++e)
        left[size_t(row_index[size_t(e)])] -= value[size_t(e)] * f;
  return left;
}

EquilibriumSystem build_equilibrium(const Assembly& a, const ContactGraph& g,
                                    const Connectivity& connectivity, const Formulation& model) {
  EquilibriumSystem s;
  const int n = int(a.bricks.size());
  std::vector<char> floating(size_t(n), 0);
  for (int b : connectivity.floating) floating[size_t(b)] = 1;
  // Rows for the grounded bricks that are not the ground themselves, in brick order.
  s.body_of.assign(size_t(n), -1);
  int bodies = 0;
  for (int i = 0; i < n; ++i)
    if (!floating[size_t(i)] && (g.fixed.empty() || !g.fixed[size_t(i)])) {
      s.body_of[size_t(i)] = bodies++;
      s.brick_of_body.push_back(i);
    }
  s.rows = EquilibriumSystem::kEquations * bodies;
  // Each body's centre (studs).
  std::vector<Vec3> brick_centre(static_cast<size_t>(n)),
      centre(static_cast<size_t>(bodies), Vec3{0, 0, 0});
  std::vector<double> mass(size_t(bodies), 0.0);
  for (int i = 0; i < n; ++i) {
    const int body = s.body_of[size_t(i)];
    if (body < 0) continue;
    brick_centre[size_t(i)] = studs(body_centre(a.bricks[size_t(i)]));
    const double m = std::max(a.bricks[size_t(i)].mass_g(), 1e-9);
    for (int k = 0; k < 3; ++k)
      centre[size_t(body)][size_t(k)] += m * brick_centre[size_t(i)][size_t(k)];
    mass[size_t(body)] += m;
  }
  for (int b = 0; b < bodies; ++b)
    for (double& c : centre[size_t(b)]) c /= mass[size_t(b)];

  std::vector<char> taken(g.contacts.size(), 0);
  for (size_t ci = 0; ci < g.contacts.size(); ++ci) {
    const Contact& c = g.contacts[ci];
    auto body = [&](int brick) { return brick == kGround ? -1 : s.body_of[size_t(brick)]; };
    const bool lower_floats = c.lower != kGround && floating[size_t(c.lower)];
    const bool upper_floats = floating[size_t(c.upper)];
    const int bl = body(c.lower), bu = body(c.upper);
    taken[ci] = !lower_floats && !upper_floats && bl != bu;
  }
  s.row_index.reserve(6 * g.friction_points.size() + 24 * g.contacts.size());
  s.value.reserve(s.row_index.capacity());
  Builder b(s, centre);

  add_friction_columns(a, g, taken, model, b);
  s.friction_columns = s.columns();

  add_push_and_support_columns(a, g, taken, model, s, b);

  s.rhs.assign(size_t(s.rows), 0.0);
  add_loads(a, g, s, brick_centre, b);
  b.drop_roundoff_loads();
  return s;
}

}  // namespace lego::physics
