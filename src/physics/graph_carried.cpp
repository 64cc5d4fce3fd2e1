// Carried parts (PHYSICS.md "Carried parts"): grouped where they touch, joined to the bricks they
// touch, by their bodies and their studs; a group's weight on what bears it, and where it
// stands on the ground or a fixed part, its support.
#include <algorithm>
#include <map>

#include "physics/contact_graph_builder.h"
#include "physics/disjoint_sets.h"

namespace lego::physics {
namespace {

// Whether two parts meet only side by side, their plans touching along a vertical line or face:
// nothing presses such faces together, so they hold none of each other's weight and tie nothing
// (docs/physics.md, "Faces that only touch"). Parts that overlap in plan rest on, hang from or
// are engaged in each other.
bool side_by_side(const OrientedBox& a, const OrientedBox& b) {
  const Box x = a.bounds(), y = b.bounds();
  for (int ax : {0, 2})
    if (std::min(x.max[ax], y.max[ax]) - std::max(x.min[ax], y.min[ax]) < kMinFace) return true;
  return false;
}

}  // namespace

struct ContactGraphBuilder::CarriedTouches {
  std::vector<int> root;                  // per carried part: its group's first part
  std::vector<std::vector<int>> touched;  // per carried part: the bricks it touches
  // Per carried part: the analysed parts that reach below its bottom where they touch it, and
  // where (in plan): what can bear its weight.
  std::vector<std::vector<std::pair<int, Rect>>> bearing;
};

void ContactGraphBuilder::gather_carried_parts() {
  if (a_.carried.empty()) return;
  const CarriedTouches t = carried_touches();
  group_carried(t);
  for (auto& group : g_.carried_groups) support_carried_group(group, t);
}

// What each carried part touches (bodies and studs within reach), and the groups they make.
ContactGraphBuilder::CarriedTouches ContactGraphBuilder::carried_touches() const {
  const int carried = int(a_.carried.size());
  std::vector<std::vector<OrientedBox>> reach = carried_boxes_;
  for (int c = 0; c < carried; ++c) {
    const auto studs = world_stud_boxes(a_.carried[size_t(c)], kKnobRimRadius);
    reach[size_t(c)].insert(reach[size_t(c)].end(), studs.begin(), studs.end());
  }
  DisjointSets groups(carried);
  CarriedTouches t;
  t.touched.resize(size_t(carried));
  t.bearing.resize(size_t(carried));
  BoxIndex carried_index;
  std::vector<int> carried_owner;
  for (int c = 0; c < carried; ++c)
    for (const auto& o : reach[size_t(c)]) {
      carried_index.add(o.bounds(), int(carried_owner.size()));
      carried_owner.push_back(c);
    }
  carried_index.finish();
  std::vector<int> box_of_carried(size_t(carried) + 1, 0);  // first box of each carried part
  for (int c = 0; c < carried; ++c)
    box_of_carried[size_t(c) + 1] = box_of_carried[size_t(c)] + int(reach[size_t(c)].size());
  // What a carried part rests on may be studs (a plant over a stud): they count as body here.
  // Only the studs of parts whose studs' extent a carried part reaches: a town's baseplates have
  // millions, which indexed all took a sixth of a contact graph's time.
  BoxIndex stud_index;
  std::vector<OrientedBox> stud_boxes;
  std::vector<int> stud_owner;
  for (int i = 0; i < n_ && carried > 0; ++i) {
    const auto& studs = shapes_[size_t(i)].studs;
    if (studs.empty()) continue;
    Box extent = stud_box(studs.front(), kKnobRimRadius);
    for (const Connector& k : studs) {
      const Box b = stud_box(k, kKnobRimRadius);
      for (int ax = 0; ax < 3; ++ax) {
        extent.min[ax] = std::min(extent.min[ax], b.min[ax]);
        extent.max[ax] = std::max(extent.max[ax], b.max[ax]);
      }
    }
    bool reached = false;
    carried_index.near(to_model(a_.bricks[size_t(i)], extent).bounds(), kCarriedReach,
                       [&](int) { reached = true; });
    if (!reached) continue;
    for (const Connector& k : studs) {
      const OrientedBox b = to_model(a_.bricks[size_t(i)], stud_box(k, kKnobRimRadius));
      stud_index.add(b.bounds(), int(stud_boxes.size()));
      stud_boxes.push_back(b);
      stud_owner.push_back(i);
    }
  }
  stud_index.finish();
  for (int c = 0; c < carried; ++c)
    for (int k = 0; k < int(reach[size_t(c)].size()); ++k) {
      // Hinge and turntable halves hold side by side: their fingers or rings engage.
      auto engages_sideways = [&](int brick) {
        return a_.carried[size_t(c)].pivots || a_.bricks[size_t(brick)].type->pivots;
      };
      auto bears = [&](int brick, const OrientedBox& o, const OrientedBox& m) {
        const Box x = o.bounds(), y = m.bounds();
        if (y.min[1] > carried_bottom_[size_t(c)] + kCarriedReach) return;
        const Rect r{std::max(x.min[0], y.min[0]), std::max(x.min[2], y.min[2]),
                     std::min(x.max[0], y.max[0]), std::min(x.max[2], y.max[2])};
        if (r.u1 >= r.u0 && r.v1 >= r.v0) t.bearing[size_t(c)].emplace_back(brick, r);
      };
      const OrientedBox& o = reach[size_t(c)][size_t(k)];
      const Box bounds = o.bounds();
      carried_index.near(bounds, kCarriedReach, [&](int other) {
        const int d = carried_owner[size_t(other)];
        if (d == c || groups.find(d) == groups.find(c)) return;
        const OrientedBox& p = reach[size_t(d)][size_t(other - box_of_carried[size_t(d)])];
        if (touch(o, p, kCarriedReach)) groups.join(c, d);
      });
      // Every box pair that touches tells where the part is borne; the part is listed once.
      auto meets = [&](int brick, const OrientedBox& m) {
        if (!touch(o, m, kCarriedReach) || (!engages_sideways(brick) && side_by_side(o, m))) return;
        bears(brick, o, m);
        auto& touched = t.touched[size_t(c)];
        if (std::find(touched.begin(), touched.end(), brick) == touched.end())
          touched.push_back(brick);
      };
      near_in_model(bounds, kCarriedReach, [&](int id) { meets(owner(id), model_box(id)); });
      stud_index.near(bounds, kCarriedReach,
                      [&](int id) { meets(stud_owner[size_t(id)], stud_boxes[size_t(id)]); });
    }
  for (int c = 0; c < carried; ++c) t.root.push_back(groups.find(c));
  return t;
}

// The groups, their mass and centre, and what each joins or rests on.
void ContactGraphBuilder::group_carried(const CarriedTouches& t) {
  const int carried = int(a_.carried.size());
  std::map<int, int> group_of_root;
  std::vector<Vec3> weighted;  // per group: Σ mass · centre
  for (int c = 0; c < carried; ++c) {
    auto [it, inserted] =
        group_of_root.try_emplace(t.root[size_t(c)], int(g_.carried_groups.size()));
    if (inserted) {
      g_.carried_groups.emplace_back();
      weighted.push_back({0, 0, 0});
    }
    CarriedGroup& group = g_.carried_groups[size_t(it->second)];
    group.carried.push_back(c);
    Vec3 centre{0, 0, 0};
    double volume = 0;
    for (const auto& o : carried_boxes_[size_t(c)]) {
      const double v = std::max(8 * o.half[0] * o.half[1] * o.half[2], 1e-9);
      for (int ax = 0; ax < 3; ++ax) centre[ax] += v * o.centre[ax];
      volume += v;
    }
    for (const Vec3& p : carried_outline_[size_t(c)])
      group.on_ground = group.on_ground || clearance(p) <= kSettleLdu;
    const double m = std::max(a_.carried[size_t(c)].mass_g, 1e-9);
    for (int ax = 0; ax < 3; ++ax) weighted[size_t(it->second)][ax] += m * centre[ax] / volume;
    group.mass_g += m;
    for (int brick : t.touched[size_t(c)]) {
      auto& list = g_.fixed[size_t(brick)] ? group.rests_on_fixed : group.joins;
      if (std::find(list.begin(), list.end(), brick) == list.end()) list.push_back(brick);
    }
  }
  for (size_t k = 0; k < g_.carried_groups.size(); ++k)
    for (int ax = 0; ax < 3; ++ax)
      g_.carried_groups[k].centre[ax] = weighted[k][ax] / g_.carried_groups[k].mass_g;
}

// Which brick bears the group's weight, whether it rests, and where it stands on the ground or a
// fixed part, its support there.
void ContactGraphBuilder::support_carried_group(CarriedGroup& group, const CarriedTouches& t) {
  std::sort(group.joins.begin(), group.joins.end());
  std::sort(group.rests_on_fixed.begin(), group.rests_on_fixed.end());
  // It rests where its centre of mass is over what bears it: the ground, a fixed part, or
  // within the span of the analysed parts under it. The one under its centre bears its
  // weight; else the one that bears it over the widest area; else the first it joins.
  Rect span;
  bool any = false;
  double widest = -1;
  const double cx = group.centre[0], cz = group.centre[2];
  auto under_centre = [&](const Rect& r) {
    return cx >= r.u0 - kMinFace / 2 && cx <= r.u1 + kMinFace / 2 && cz >= r.v0 - kMinFace / 2 &&
           cz <= r.v1 + kMinFace / 2;
  };
  for (int c : group.carried)
    for (const auto& [brick, r] : t.bearing[size_t(c)]) {
      if (g_.fixed[size_t(brick)]) continue;
      grow(span, any, r);
      const double area = r.area() + (under_centre(r) ? 1e12 : 0);
      if (area > widest) widest = area, group.bearer = brick;
    }
  // Tied to one another by the group, its parts bear it together: the first, where the tree
  // of its joints is rooted, takes its weight.
  if (!group.joins.empty() && (group.bearer < 0 || (group.assumed_joint() && assumed_joints_)))
    group.bearer = group.joins.front();
  group.rests = group.on_ground || !group.rests_on_fixed.empty() || (any && under_centre(span));
  if (group.joins.empty() || (!group.on_ground && group.rests_on_fixed.empty())) return;
  // Where the group stands on the ground or a fixed part, it holds the body it joins like
  // the ground does: it pushes and holds sideways.
  // It stands on its lowest points (a tyre on a strip across its tread): on the table,
  // those nearest it, where it is nearest; on a fixed part, those at its bottom.
  double bottom = 1e300, nearest = 1e300, table_there = 0;
  for (int c : group.carried) {
    bottom = std::min(bottom, carried_bottom_[size_t(c)]);
    for (const Vec3& p : carried_outline_[size_t(c)])
      if (clearance(p) < nearest) nearest = clearance(p), table_there = table_.at(p[0], p[2]);
  }
  Meeting& m = meeting(group.on_ground ? kGround : group.rests_on_fixed.front(), group.bearer,
                       kPlusY, group.on_ground ? table_there : bottom, /*in_model=*/true);
  for (int c : group.carried)
    for (const Vec3& p : carried_outline_[size_t(c)])
      if (group.on_ground ? clearance(p) <= kSettleLdu : p[1] <= bottom + kCarriedReach)
        grow(m.patch, m.has_patch, {p[0], p[2], p[0], p[2]});
  widen_to_min_face(m.patch);
  m.support = true;
}

}  // namespace lego::physics
