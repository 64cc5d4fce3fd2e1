#include "physics/contact_graph.h"

#include <algorithm>
#include <cmath>

#include "physics/contact_graph_builder.h"

namespace lego::physics {

void grow(Rect& r, bool& has, const Rect& add) {
  if (!has) {
    r = add;
    has = true;
    return;
  }
  r.u0 = std::min(r.u0, add.u0), r.v0 = std::min(r.v0, add.v0);
  r.u1 = std::max(r.u1, add.u1), r.v1 = std::max(r.v1, add.v1);
}

void widen_to_min_face(Rect& r) {
  if (r.u1 - r.u0 < kMinFace) r.u0 -= kMinFace / 2, r.u1 += kMinFace / 2;
  if (r.v1 - r.v0 < kMinFace) r.v0 -= kMinFace / 2, r.v1 += kMinFace / 2;
}

Rect in_plane(const Box& b, int axis) {
  const int f = kInPlane[axis][0], s = kInPlane[axis][1];
  return {b.min[f], b.min[s], b.max[f], b.max[s]};
}

Vec3 body_centre(const Brick& brick) {
  const WorldShape w = world_shape(brick);
  Vec3 sum{0, 0, 0};
  double volume = 0;
  for (const Box& b : w.body) {
    const double v = std::max(b.volume(), 1e-9);
    for (int a = 0; a < 3; ++a) sum[a] += v * (b.min[a] + b.max[a]) / 2;
    volume += v;
  }
  for (double& c : sum) c /= volume;
  // A wheel or a tyre is round about its axle: its mass centre is on that line, wherever the
  // boxes that stand for its body put theirs.
  if (brick.type->rolls)
    for (const Shaft& s : w.shafts)
      if (s.kind == Shaft::Kind::Rim || s.kind == Shaft::Kind::Tyre) {
        const int axis = s.axis();
        for (int a : {(axis + 1) % 3, (axis + 2) % 3}) sum[size_t(a)] = s.a[size_t(a)];
        break;
      }
  return to_model(brick, sum);
}

ContactGraph ContactGraph::build(const Assembly& a, GroundMode ground, bool assumed_joints,
                                 const Budget* budget) {
  return ContactGraphBuilder(a, ground, assumed_joints, budget, true).build();
}

ContactGraph ContactGraph::connections(const Assembly& a, GroundMode ground, const Budget* budget) {
  return ContactGraphBuilder(a, ground, true, budget, false).build();
}

bool ContactGraph::pairwise() const {
  return carried_groups.empty();
}

ContactGraph ContactGraph::among(const std::vector<int>& parts) const {
  ContactGraph out;
  out.ground = ground;
  out.ground_height = ground_height;
  out.ground_slope = ground_slope;  // tips_over is the whole model's (analyze_contacts): not kept
  std::vector<int> here(contacts_of.size(), -1);  // per part of this graph: its index there
  for (size_t k = 0; k < parts.size(); ++k) here[size_t(parts[k])] = int(k);
  out.contacts_of.resize(parts.size());
  out.fixed.reserve(parts.size());
  for (int p : parts) out.fixed.push_back(fixed[size_t(p)]);
  // In this graph's order, which build() gives the parts' contacts in whatever else is there
  // (ContactGraphBuilder::add_meeting_contacts sorts them by the parts' order, which `parts`
  // keeps; the joints follow, by pairs of parts).
  std::vector<int> kept_as(contacts.size(), -1);
  for (size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    const int upper = here[size_t(c.upper)];
    const int lower = c.lower == kGround ? kGround : here[size_t(c.lower)];
    if (upper < 0 || (c.lower != kGround && lower < 0)) continue;
    kept_as[k] = int(out.contacts.size());
    Contact kept = c;
    kept.upper = upper;
    kept.lower = lower;
    kept.first_point = uint32_t(out.friction_points.size());
    out.friction_points.insert(out.friction_points.end(), friction_points.begin() + c.first_point,
                               friction_points.begin() + c.first_point + c.point_count);
    if (lower != kGround) out.contacts_of[size_t(lower)].push_back(kept_as[k]);
    out.contacts_of[size_t(upper)].push_back(kept_as[k]);
    out.contacts.push_back(kept);
  }
  auto joints = [&](const std::vector<int>& of, std::vector<int>& into) {
    for (int k : of)
      if (kept_as[size_t(k)] >= 0) into.push_back(kept_as[size_t(k)]);
  };
  joints(lattice_joints, out.lattice_joints);
  joints(pivot_joints, out.pivot_joints);
  joints(shaft_joints, out.shaft_joints);
  for (const auto& [i, j] : overlaps)
    if (here[size_t(i)] >= 0 && here[size_t(j)] >= 0)
      out.overlaps.emplace_back(here[size_t(i)], here[size_t(j)]);
  return out;
}

ContactGraphBuilder::ContactGraphBuilder(const Assembly& a, GroundMode ground, bool assumed_joints,
                                         const Budget* budget, bool friction_points)
    : a_(a),
      n_(int(a.bricks.size())),
      assumed_joints_(assumed_joints),
      friction_points_(friction_points),
      budget_(budget) {
  g_.ground = ground;
  g_.contacts_of.resize(size_t(n_));
  g_.fixed.assign(size_t(n_), 0);
}

ContactGraph ContactGraphBuilder::build() && {
  shape_parts();
  find_ground();
  index_parts();
  engage_studs();
  engage_studs_across_lattices();
  touch_faces();
  stand_on_ground();
  gather_carried_parts();
  merge_faces_into_stud_connections();
  add_meeting_contacts();
  join_shafts();
  tie_carried_joints();
  join_lattices_and_pivots();
  return std::move(g_);
}

void ContactGraphBuilder::check_time(int i) const {
  if (budget_ && i % 256 == 0) budget_->check(kContactGraph, size_t(i), size_t(n_));
}

int ContactGraphBuilder::frame_of(int i) const {
  return a_.bricks[size_t(i)].frame ? a_.bricks[size_t(i)].frame->id : -1;
}

const Box& ContactGraphBuilder::box(int id) const {
  return shapes_[size_t(owner(id))].body[size_t(box_owner_[size_t(id)].second)];
}

OrientedBox ContactGraphBuilder::model_box(int id) const {
  return to_model(a_.bricks[size_t(owner(id))], box(id));
}

Meeting& ContactGraphBuilder::meeting(int lower, int upper, int direction, double plane,
                                      bool in_model) {
  const bool turned = !in_model && a_.bricks[size_t(upper)].frame;
  Meeting& m = meetings_[{lower, upper, direction, snap_steps(plane), turned}];
  m.lower = lower, m.upper = upper, m.direction = direction, m.plane = plane;
  m.turned = turned;
  return m;
}

int ContactGraphBuilder::add_contact(const Contact& c) {
  const int index = int(g_.contacts.size());
  if (c.lower != kGround) g_.contacts_of[size_t(c.lower)].push_back(index);
  g_.contacts_of[size_t(c.upper)].push_back(index);
  g_.contacts.push_back(c);
  return index;
}

bool ContactGraphBuilder::on_ground(double y) const {
  return table_.level() && std::abs(y - ground_y_) <= kTouch;
}

double ContactGraphBuilder::clearance(const Vec3& p) const {
  return p[1] - table_.at(p[0], p[2]);
}

// Each brick's shape where the assembly puts it, and each carried part's boxes and outline.
void ContactGraphBuilder::shape_parts() {
  shapes_.reserve(size_t(n_));
  brick_bottom_.reserve(size_t(n_));
  for (const Brick& b : a_.bricks) {
    check_time(int(shapes_.size()));
    shapes_.push_back(world_shape(b));
    any_turned_ = any_turned_ || b.frame;
    double bottom = 1e300;
    for (const Box& box : shapes_.back().body)
      bottom = std::min(bottom, model_bounds(b, box).min[1]);
    brick_bottom_.push_back(bottom);
  }
  for (const CarriedPart& c : a_.carried) {
    carried_boxes_.push_back(world_boxes(c));
    carried_outline_.push_back(world_outline(c));
    double bottom = 1e300;
    for (const Vec3& p : carried_outline_.back()) bottom = std::min(bottom, p[1]);
    carried_bottom_.push_back(bottom);
  }
}

// The ground: the table the model rests on, given (physics/table.h: settle_on_table), or level
// at its lowest point. At that point a baseplate is the ground, and the ground's studs engage
// there.
void ContactGraphBuilder::find_ground() {
  table_.slope = a_.ground_slope;
  double ground_y = 1e300;
  for (int i = 0; i < n_; ++i)
    if (!shapes_[size_t(i)].body.empty()) ground_y = std::min(ground_y, brick_bottom_[size_t(i)]);
  for (double bottom : carried_bottom_) ground_y = std::min(ground_y, bottom);
  if (ground_y > 1e299) ground_y = 0;
  if (a_.ground_height && table_.level()) ground_y = *a_.ground_height;
  ground_y_ = ground_y;
  table_.height = a_.ground_height.value_or(ground_y);
  g_.ground_height = table_.height;
  g_.ground_slope = table_.slope;
  for (int i = 0; i < n_; ++i) {
    const bool bottom = brick_bottom_[size_t(i)] <= ground_y + kSettleLdu;
    g_.fixed[size_t(i)] =
        a_.bricks[size_t(i)].fixed || (a_.bricks[size_t(i)].type->baseplate && bottom);
  }
}

// Receptacles by where they are, bodies by the cells they cover.
void ContactGraphBuilder::index_parts() {
  size_t receptacle_count = 0;
  for (const WorldShape& s : shapes_) receptacle_count += s.receptacles.size() + s.bores.size();
  receptacles_.reserve(receptacle_count);
  // Cells and bores in one index: a bore's neighbours half a stud off are never cells, so the
  // friction points of a stud in a bore follow the part's row of tubes as a cell's follow its
  // cells.
  for (int i = 0; i < n_; ++i) {
    for (const Connector& c : shapes_[size_t(i)].receptacles) receptacles_.add(c, i);
    for (const Connector& c : shapes_[size_t(i)].bores) receptacles_.add(c, i);
  }
  for (int i = 0; i < n_; ++i)
    for (int k = 0; k < int(shapes_[size_t(i)].body.size()); ++k) {
      index_.add(shapes_[size_t(i)].body[size_t(k)], int(box_owner_.size()));
      box_owner_.emplace_back(i, k);
    }
  index_.finish();
  // `index_` holds each box in its brick's lattice frame, so the boxes of turned bricks are found
  // again, by where the model puts them, in `turned_index_`.
  if (any_turned_) {
    for (int id = 0; id < int(box_owner_.size()); ++id)
      if (const Brick& b = a_.bricks[size_t(owner(id))]; b.frame)
        turned_index_.add(model_bounds(b, box(id)), id);
    turned_index_.finish();
  }
}

// A stud connection pointing down or to a low side meets the faces there from the other side.
void ContactGraphBuilder::merge_faces_into_stud_connections() {
  for (auto& [key, m] : meetings_) {
    if (m.receptacles.empty() || sign_of(m.direction) > 0 || m.lower == kGround) continue;
    auto face =
        meetings_.find({m.upper, m.lower, opposite(m.direction), snap_steps(m.plane), m.turned});
    if (face == meetings_.end() || !face->second.receptacles.empty()) continue;
    if (face->second.has_patch) grow(m.patch, m.has_patch, face->second.patch);
    face->second.has_patch = false;  // one contact for both
  }
}

// The meetings as contacts, in a fixed order: along the vertical first, by the part above; then
// across x and z, by the part on the low side.
void ContactGraphBuilder::add_meeting_contacts() {
  std::vector<Meeting*> ordered;
  ordered.reserve(meetings_.size());
  for (auto& [key, m] : meetings_) {
    if (m.receptacles.empty() && !m.has_patch) continue;
    ordered.push_back(&m);
  }
  auto order_key = [](const Meeting* m) {
    const int axis = axis_of(m->direction);
    const bool positive = sign_of(m->direction) > 0;
    const int primary =
        axis == 1 ? (positive ? m->upper : m->lower) : (positive ? m->lower : m->upper);
    const double f0 = m->has_patch ? m->patch.u0 : 0, s0 = m->has_patch ? m->patch.v0 : 0;
    // The plane and the lattice last: two meetings of one pair can differ only there (a part of
    // several boxes), and the sort, not stable, would order them as the other meetings around
    // them fall (ContactGraph::among takes a step's contacts from the whole model's in order).
    return std::make_tuple(axis == 1 ? 0 : 1, primary, axis, f0, s0, m->lower, m->upper,
                           m->direction, m->plane, m->turned);
  };
  std::sort(ordered.begin(), ordered.end(),
            [&](const Meeting* x, const Meeting* y) { return order_key(x) < order_key(y); });
  for (Meeting* m : ordered) {
    Contact c;
    c.lower = m->lower;
    c.upper = m->upper;
    c.direction = m->direction;
    c.plane = m->plane;
    c.support = m->support;
    c.turned = m->turned;
    const int axis = axis_of(m->direction), f = kInPlane[axis][0], s = kInPlane[axis][1];
    if (!m->receptacles.empty()) {
      auto& rs = m->receptacles;
      std::sort(rs.begin(), rs.end(), [&](const Vec3& x, const Vec3& y) {
        return std::pair(x[size_t(f)], x[size_t(s)]) < std::pair(y[size_t(f)], y[size_t(s)]);
      });
      rs.erase(std::unique(rs.begin(), rs.end()), rs.end());
      c.studs = int(rs.size());
      c.support = true;
      c.first_point = uint32_t(g_.friction_points.size());
      if (friction_points_ && !(g_.ground == GroundMode::Table && c.lower == kGround))
        for (const Vec3& r : rs)
          add_friction_points(receptacles_, c.upper, r, opposite(m->direction), g_.friction_points);
      c.point_count = uint32_t(g_.friction_points.size()) - c.first_point;
      if (!m->has_patch) {  // the bodies do not meet (a recessed stud): the studs' cells
        // Across lattices, where both parts surely are: the square inside the circle that the
        // stud's cell in each part holds, whichever way the two are turned.
        const double half = m->across ? kStudPitch / (2 * std::sqrt(2.0)) : kStudPitch / 2;
        for (const Vec3& r : rs)
          grow(
              m->patch, m->has_patch,
              {r[size_t(f)] - half, r[size_t(s)] - half, r[size_t(f)] + half, r[size_t(s)] + half});
      }
    }
    c.patch = m->patch;
    if (!c.snap() && c.lower != kGround && frame_of(c.lower) == frame_of(c.upper)) {
      for (const Connector& k : shapes_[size_t(c.lower)].studs) {
        if (k.direction != c.direction || std::abs(k.at[size_t(axis)] - c.plane) > kTouch) continue;
        const double kf = k.at[size_t(f)], ks = k.at[size_t(s)];
        if (kf > c.patch.u0 + kMinFace && kf < c.patch.u1 - kMinFace &&
            ks > c.patch.v0 + kMinFace && ks < c.patch.v1 - kMinFace) {
          c.misaligned = true;
          break;
        }
      }
    }
    add_contact(c);
  }
}

}  // namespace lego::physics
