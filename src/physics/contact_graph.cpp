#include "physics/contact_graph.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <unordered_map>

#include "physics/disjoint_sets.h"
#include "physics/knob_grip.h"
#include "physics/table.h"
#include "physics/world_shape.h"

namespace lego::physics {
namespace {

// Faces closer than this (LDU) touch; bodies sharing more than this on every axis overlap.
constexpr double kTouch = 0.25;
// Faces that share less than this across (LDU) meet along an edge: no contact to push on.
constexpr double kMinFace = 1.0;
// A carried part joins what comes within this of its body (PHYSICS.md: 1 LDU).
constexpr double kCarriedReach = 1.0;
constexpr double kSettle = kSettleLdu;
constexpr double kStudPitch = kLduPerStud;

// The in-plane axes of a contact along `axis`, in the order its columns have always had: across
// a horizontal plane x then z, across a vertical one y first.
constexpr int kInPlane[3][2] = {{1, 2}, {0, 2}, {1, 0}};

int64_t q(double v) {
  return std::llround(v / kSnap);
}

struct PointKey {
  int64_t x, y, z;
  int direction;
  friend bool operator==(const PointKey&, const PointKey&) = default;
};
struct PointKeyHash {
  size_t operator()(const PointKey& k) const {
    uint64_t h = uint64_t(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= uint64_t(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return size_t(h ^ uint64_t(k.direction));
  }
};
PointKey key_of(const Vec3& p, int direction) {
  return {q(p[0]), q(p[1]), q(p[2]), direction};
}

// Every receptacle of the assembly by position and facing; duplicates chain through `next`.
class ReceptacleIndex {
 public:
  struct Entry {
    Vec3 at;
    int direction, brick, next;
  };
  void add(const Connector& c, int brick) {
    const int index = int(entries_.size());
    auto [it, inserted] = first_.try_emplace(key_of(c.at, c.direction), index);
    entries_.push_back({c.at, c.direction, brick, inserted ? -1 : it->second});
    if (!inserted) it->second = index;
  }
  // The first entry at p facing `direction`, or -1; follow Entry::next for the others.
  int find(const Vec3& p, int direction) const {
    auto it = first_.find(key_of(p, direction));
    return it == first_.end() ? -1 : it->second;
  }
  bool owned_by(const Vec3& p, int direction, int brick) const {
    for (int e = find(p, direction); e >= 0; e = entries_[size_t(e)].next)
      if (entries_[size_t(e)].brick == brick) return true;
    return false;
  }
  const Entry& operator[](int e) const { return entries_[size_t(e)]; }
  void reserve(size_t n) {
    first_.reserve(n);
    entries_.reserve(n);
  }

 private:
  std::unordered_map<PointKey, int, PointKeyHash> first_;
  std::vector<Entry> entries_;
};

// Boxes by the cells (one stud across, one brick high) they cover: a box finds what it touches
// or overlaps by looking in the cells of its closed range.
class BoxIndex {
 public:
  static constexpr double kCell[3] = {kLduPerStud, kLduPerPlate* kPlatesPerBrick, kLduPerStud};

  void add(const Box& b, int id) {
    if (cell_count(b, 0) > kMaxCellsPerBox)
      large_.push_back(id);
    else
      for_cells(b, 0, [&](uint64_t cell) { cells_.emplace_back(cell, id); });
  }
  void finish() { std::sort(cells_.begin(), cells_.end()); }
  // Calls f(id) for every box in a cell that `b`, grown by `margin`, reaches; ids may repeat.
  template <class F>
  void near(const Box& b, double margin, F&& f) const {
    for (int id : large_) f(id);
    if (cell_count(b, margin) > double(cells_.size())) {  // cheaper to name them all
      for (const auto& [cell, id] : cells_) f(id);
      return;
    }
    for_cells(b, margin, [&](uint64_t cell) {
      auto it = std::lower_bound(cells_.begin(), cells_.end(), std::pair<uint64_t, int>(cell, -1));
      for (; it != cells_.end() && it->first == cell; ++it) f(it->second);
    });
  }

 private:
  // A box over this many cells is kept apart and met by every query: a part scaled a
  // millionfold (a carried 1x8 brick 160 km long, found by the fuzzer) once filled 8 million
  // cells and took 25 s to index.
  static constexpr double kMaxCellsPerBox = 4096;
  // Cells are counted within ±2^20 of the origin (±21 km): farther parts share the last cell.
  static constexpr int64_t kOffset = int64_t(1) << 20;

  std::vector<std::pair<uint64_t, int>> cells_;
  std::vector<int> large_;

  static int64_t cell(double v, int axis) {
    const double c = std::floor(v / kCell[axis]);
    if (!(c > double(-kOffset))) return -kOffset + 1;  // NaN too
    return int64_t(std::min(c, double(kOffset - 1)));
  }
  static void range(const Box& b, double margin, int64_t lo[3], int64_t hi[3]) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = cell(b.min[a] - margin, a);
      hi[a] = margin > 0 ? cell(b.max[a] + margin, a) : cell(b.max[a] - 1e-9, a);
      hi[a] = std::max(hi[a], lo[a]);
    }
  }
  static double cell_count(const Box& b, double margin) {
    int64_t lo[3], hi[3];
    range(b, margin, lo, hi);
    return double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
  }
  // A box claims the cells of [min, max); a query with a margin reaches [min - m, max + m].
  template <class F>
  static void for_cells(const Box& b, double margin, F&& f) {
    int64_t lo[3], hi[3];
    range(b, margin, lo, hi);
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
          f((uint64_t(x + kOffset) << 42) | (uint64_t(y + kOffset) << 21) | uint64_t(z + kOffset));
  }
};

// A contact being gathered: its parts, plane and what meets there.
struct Meeting {
  int lower = kGround, upper = 0, direction = kPlusY;
  double plane = 0;
  bool has_patch = false;
  Rect patch;
  std::vector<Vec3> receptacles;  // engaged, in `upper`
  bool support = false;
  bool turned = false;  // in the lattice frame of `upper`, which is turned (Contact::turned)
  bool across = false;  // studs of one lattice in receptacles of another
};

void grow(Rect& r, bool& has, const Rect& add) {
  if (!has) {
    r = add;
    has = true;
    return;
  }
  r.u0 = std::min(r.u0, add.u0), r.v0 = std::min(r.v0, add.v0);
  r.u1 = std::max(r.u1, add.u1), r.v1 = std::max(r.v1, add.v1);
}

Rect in_plane(const Box& b, int axis) {
  const int f = kInPlane[axis][0], s = kInPlane[axis][1];
  return {b.min[f], b.min[s], b.max[f], b.max[s]};
}

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

// Friction points of one engaged stud: where it touches `upper`'s receptacle at `r`, by the
// receptacles around it (PHYSICS.md "Stud connection").
void add_friction_points(const ReceptacleIndex& all, int upper, const Vec3& r, int facing,
                         std::vector<FrictionPoint>& out) {
  const int axis = axis_of(facing), f = kInPlane[axis][0], s = kInPlane[axis][1];
  auto has = [&](int df, int ds) {
    Vec3 p = r;
    p[size_t(f)] += df * kStudPitch;
    p[size_t(s)] += ds * kStudPitch;
    return all.owned_by(p, facing, upper);
  };
  const bool along_f = has(1, 0), back_f = has(-1, 0), along_s = has(0, 1), back_s = has(0, -1);
  uint8_t touched = 0;  // the directions of the contacts (knob_grip.h)
  auto touch = [&](int df, int ds) {
    for (int d = 0; d < kGripDirections; ++d)
      if (kGripStep[d][0] == df && kGripStep[d][1] == ds) touched |= uint8_t(1u << d);
  };
  // A wall where the receptacles end; in a row one stud wide also the pins between them.
  const bool row_f = !along_s && !back_s, row_s = !along_f && !back_f;
  if (!along_f || row_f) touch(1, 0);
  if (!back_f || row_f) touch(-1, 0);
  if (!along_s || row_s) touch(0, 1);
  if (!back_s || row_s) touch(0, -1);
  // A tube between four studs: where the three neighbouring receptacles are all there.
  for (int df : {1, -1})
    for (int ds : {1, -1})
      if ((df > 0 ? along_f : back_f) && (ds > 0 ? along_s : back_s) && has(df, ds)) touch(df, ds);
  const GripShares& grip = grip_shares(touched);
  // Walls and pins first, then tubes: the order the columns have always had.
  for (int d : {0, 4, 2, 6, 1, 7, 3, 5}) {
    // A contact the knob's balance leaves unpressed holds nothing.
    if (!(touched & (1u << d)) || grip.share[size_t(d)] < 1e-9) continue;
    const double step = kGripStep[d][0] && kGripStep[d][1] ? 1 / std::sqrt(2.0) : 1;
    Vec3 p = r;
    p[size_t(f)] += kGripStep[d][0] * step * kKnobRimRadius;
    p[size_t(s)] += kGripStep[d][1] * step * kKnobRimRadius;
    out.push_back({p[0], p[1], p[2], grip.share[size_t(d)]});
  }
}

}  // namespace

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
  return to_model(brick, sum);
}

ContactGraph ContactGraph::build(const Assembly& a, GroundMode ground, bool assumed_joints,
                                 const Budget* budget) {
  ContactGraph g;
  g.ground = ground;
  const int n = int(a.bricks.size());
  // Each pass over the parts counts them again: the count says where in a pass it stopped.
  auto check_time = [&](int i) {
    if (budget && i % 256 == 0) budget->check(kContactGraph, size_t(i), size_t(n));
  };
  g.contacts_of.resize(size_t(n));
  g.fixed.assign(size_t(n), 0);

  std::vector<WorldShape> shapes;
  shapes.reserve(size_t(n));
  size_t receptacle_count = 0;
  bool any_turned = false;
  std::vector<double> brick_bottom;  // each brick's lowest point in the model (lattice frame)
  brick_bottom.reserve(size_t(n));
  for (const Brick& b : a.bricks) {
    check_time(int(shapes.size()));
    shapes.push_back(world_shape(b));
    receptacle_count += shapes.back().receptacles.size() + shapes.back().bores.size();
    any_turned = any_turned || b.frame;
    double bottom = 1e300;
    for (const Box& box : shapes.back().body)
      bottom = std::min(bottom, model_bounds(b, box).min[1]);
    brick_bottom.push_back(bottom);
  }
  // Parts meet by their studs and faces only on one lattice (README "What it analyses", turned
  // lattices).
  auto frame_of = [&](int i) {
    return a.bricks[size_t(i)].frame ? a.bricks[size_t(i)].frame->id : -1;
  };
  std::vector<std::vector<OrientedBox>> carried_boxes;
  std::vector<std::vector<Vec3>> carried_outline;
  std::vector<double> carried_bottom;  // the lowest point of each carried part
  for (const CarriedPart& c : a.carried) {
    carried_boxes.push_back(world_boxes(c));
    carried_outline.push_back(world_outline(c));
    double bottom = 1e300;
    for (const Vec3& p : carried_outline.back()) bottom = std::min(bottom, p[1]);
    carried_bottom.push_back(bottom);
  }

  // The ground: the table the model rests on, given (physics/table.h: settle_on_table), or
  // level at its lowest point. At that point a baseplate is the ground, and the ground's studs
  // engage there.
  Table table;
  table.slope = a.ground_slope;
  double ground_y = 1e300;
  for (int i = 0; i < n; ++i)
    if (!shapes[size_t(i)].body.empty()) ground_y = std::min(ground_y, brick_bottom[size_t(i)]);
  for (double bottom : carried_bottom) ground_y = std::min(ground_y, bottom);
  if (ground_y > 1e299) ground_y = 0;
  if (a.ground_height && table.level()) ground_y = *a.ground_height;
  table.height = a.ground_height.value_or(ground_y);
  g.ground_height = table.height;
  g.ground_slope = table.slope;
  auto on_ground = [&](double y) { return table.level() && std::abs(y - ground_y) <= kTouch; };
  for (int i = 0; i < n; ++i) {
    const bool bottom = brick_bottom[size_t(i)] <= ground_y + kSettle;
    g.fixed[size_t(i)] =
        a.bricks[size_t(i)].fixed || (a.bricks[size_t(i)].type->baseplate && bottom);
  }
  // How far above the table a point is.
  auto clearance = [&](const Vec3& p) { return p[1] - table.at(p[0], p[2]); };

  ReceptacleIndex receptacles;
  receptacles.reserve(receptacle_count);
  // Cells and bores in one index: a bore's neighbours half a stud off are never cells, so the
  // friction points of a stud in a bore follow the part's row of tubes as a cell's follow its
  // cells.
  for (int i = 0; i < n; ++i) {
    for (const Connector& c : shapes[size_t(i)].receptacles) receptacles.add(c, i);
    for (const Connector& c : shapes[size_t(i)].bores) receptacles.add(c, i);
  }
  BoxIndex index;
  std::vector<std::pair<int, int>> box_owner;  // (brick, box of its body)
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < int(shapes[size_t(i)].body.size()); ++k) {
      index.add(shapes[size_t(i)].body[size_t(k)], int(box_owner.size()));
      box_owner.emplace_back(i, k);
    }
  index.finish();
  auto box = [&](int id) -> const Box& {
    return shapes[size_t(box_owner[size_t(id)].first)].body[size_t(box_owner[size_t(id)].second)];
  };
  // Where bodies are in the model: `index` holds each box in its brick's lattice frame, so the
  // boxes of turned bricks are found again, by where the model puts them, in `turned_index`.
  BoxIndex turned_index;
  if (any_turned) {
    for (int id = 0; id < int(box_owner.size()); ++id)
      if (const Brick& b = a.bricks[size_t(box_owner[size_t(id)].first)]; b.frame)
        turned_index.add(model_bounds(b, box(id)), id);
    turned_index.finish();
  }
  auto model_box = [&](int id) {
    return to_model(a.bricks[size_t(box_owner[size_t(id)].first)], box(id));
  };
  // Calls f(id) for the boxes near `bounds` (the model's lattice frame); ids may repeat.
  auto near_in_model = [&](const Box& bounds, double margin, auto&& f) {
    index.near(bounds, margin, [&](int id) {
      if (!a.bricks[size_t(box_owner[size_t(id)].first)].frame) f(id);
    });
    if (any_turned) turned_index.near(bounds, margin, f);
  };

  // Meetings keyed by (lower, upper, direction, plane, turned): stud engagements and touching
  // faces.
  std::map<std::tuple<int, int, int, int64_t, bool>, Meeting> meetings;
  auto meeting = [&](int lower, int upper, int direction, double plane,
                     bool in_model = false) -> Meeting& {
    const bool turned = !in_model && a.bricks[size_t(upper)].frame;
    Meeting& m = meetings[{lower, upper, direction, q(plane), turned}];
    m.lower = lower, m.upper = upper, m.direction = direction, m.plane = plane;
    m.turned = turned;
    return m;
  };

  // Studs in receptacles, along any axis.
  for (int l = 0; l < n; ++l) {
    check_time(l);
    for (const Connector& s : shapes[size_t(l)].studs)
      for (int e = receptacles.find(s.at, opposite(s.direction)); e >= 0; e = receptacles[e].next) {
        const int u = receptacles[e].brick;
        if (u == l || (g.fixed[size_t(l)] && g.fixed[size_t(u)]) || frame_of(u) != frame_of(l))
          continue;
        meeting(l, u, s.direction, s.at[size_t(axis_of(s.direction))])
            .receptacles.push_back(receptacles[e].at);
      }
  }

  // Studs in receptacles of another lattice, both upright (README "What it analyses", turned
  // lattices): a stud in a receptacle is a connection however the two parts are turned about it
  // (the water tower's ring of 1 x 3 bricks, each turned on a stud of the one below). Found where
  // the model puts them: the corpus places such rings by eye, a stud up to 3 LDU from the
  // receptacle it is in, so within the receptacle's cell (kStudInCellLdu). Two parts joined by
  // more than one stud cannot be turned against each other: their studs must then be off their
  // receptacles by one common shift (within the LDU a part placed by eye strays), else none of
  // them is in a receptacle.
  std::set<std::pair<int, int>> snapped_across;
  if (any_turned) {
    // Upright parts of turned lattices, and the parts of other lattices within reach of them.
    std::vector<char> across(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
      const Brick& b = a.bricks[size_t(i)];
      if (!b.frame || tilted(*b.frame)) continue;
      across[size_t(i)] = 1;
      for (const Box& box : shapes[size_t(i)].body)
        near_in_model(model_bounds(b, box), kCarriedReach, [&](int id) {
          const int j = box_owner[size_t(id)].first;
          const Brick& other = a.bricks[size_t(j)];
          if (!other.frame || !tilted(*other.frame)) across[size_t(j)] = 1;
        });
    }
    auto vertical = [](const Connector& c) { return axis_of(c.direction) == 1; };
    constexpr double kCell = kStudInCellLdu;
    auto cell = [&](const Vec3& p, int direction) {
      return std::tuple(int64_t(std::floor(p[0] / kCell)), int64_t(std::floor(p[1] / kCell)),
                        int64_t(std::floor(p[2] / kCell)), direction);
    };
    using Cell = decltype(cell(Vec3{}, 0));
    struct Placed {
      Cell cell;
      Vec3 at, model;
      int brick;
    };
    std::vector<Placed> placed;
    for (int i = 0; i < n; ++i)
      if (across[size_t(i)])
        for (const Connector& r : shapes[size_t(i)].receptacles)
          if (vertical(r)) {
            const Vec3 m = to_model(a.bricks[size_t(i)], r.at);
            placed.push_back({cell(m, r.direction), r.at, m, i});
          }
    std::sort(placed.begin(), placed.end(),
              [](const Placed& x, const Placed& y) { return x.cell < y.cell; });
    struct Engaged {
      int lower, upper, direction;
      Vec3 at;     // the receptacle, in the upper part's lattice frame
      Vec3 shift;  // from the stud to the receptacle, in the model
    };
    std::vector<Engaged> engaged;
    for (int l = 0; l < n; ++l) {
      if (!across[size_t(l)]) continue;
      for (const Connector& k : shapes[size_t(l)].studs) {
        if (!vertical(k)) continue;
        const Vec3 m = to_model(a.bricks[size_t(l)], k.at);
        const auto [x, y, z, facing] = cell(m, opposite(k.direction));
        for (int64_t dx = -1; dx <= 1; ++dx)
          for (int64_t dy = -1; dy <= 1; ++dy)
            for (int64_t dz = -1; dz <= 1; ++dz) {
              const Cell key{x + dx, y + dy, z + dz, facing};
              auto it = std::lower_bound(placed.begin(), placed.end(), key,
                                         [](const Placed& p, const Cell& c) { return p.cell < c; });
              for (; it != placed.end() && it->cell == key; ++it) {
                const int u = it->brick;
                if (u == l || frame_of(u) == frame_of(l) ||
                    (g.fixed[size_t(l)] && g.fixed[size_t(u)]))
                  continue;
                const Vec3 shift{it->model[0] - m[0], it->model[1] - m[1], it->model[2] - m[2]};
                if (std::abs(shift[1]) > kTouch || std::hypot(shift[0], shift[2]) > kStudInCellLdu)
                  continue;
                engaged.push_back({l, u, k.direction, it->at, shift});
              }
            }
      }
    }
    std::stable_sort(engaged.begin(), engaged.end(), [](const Engaged& x, const Engaged& y) {
      return std::pair(x.lower, x.upper) < std::pair(y.lower, y.upper);
    });
    for (size_t first = 0, last = 0; first < engaged.size(); first = last) {
      while (last < engaged.size() && engaged[last].lower == engaged[first].lower &&
             engaged[last].upper == engaged[first].upper)
        ++last;
      bool common = true;
      for (size_t i = first; i < last && common; ++i)
        for (size_t j = first; j < i && common; ++j)
          common = std::hypot(engaged[i].shift[0] - engaged[j].shift[0],
                              engaged[i].shift[2] - engaged[j].shift[2]) <= kCarriedReach;
      if (!common) continue;
      for (size_t i = first; i < last; ++i) {
        const Engaged& e = engaged[i];
        Meeting& meet = meeting(e.lower, e.upper, e.direction, e.at[1]);
        meet.receptacles.push_back(e.at);
        meet.across = true;
      }
      snapped_across.emplace(std::min(engaged[first].lower, engaged[first].upper),
                             std::max(engaged[first].lower, engaged[first].upper));
    }
  }

  // Faces that touch, and bodies that overlap.
  // A box in several cells is met once per cell: the candidates are gathered, then taken once
  // each (a baseplate near thousands of parts made a search of those seen quadratic).
  std::vector<int> near;
  for (int id = 0; id < int(box_owner.size()); ++id) {
    const Box& bi = box(id);
    const int i = box_owner[size_t(id)].first;
    if (id == 0 || box_owner[size_t(id - 1)].first != i) check_time(i);
    near.clear();
    index.near(bi, kTouch, [&](int other) {
      if (other > id && box_owner[size_t(other)].first != i) near.push_back(other);
    });
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    for (const int other : near) {
      const Box& bj = box(other);
      const int j = box_owner[size_t(other)].first;
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
        g.overlaps.emplace_back(std::min(i, j), std::max(i, j));
        continue;
      }
      if (shared != 2 || wide != 2 || touching < 0 || (g.fixed[size_t(i)] && g.fixed[size_t(j)]))
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
  std::sort(g.overlaps.begin(), g.overlaps.end());
  g.overlaps.erase(std::unique(g.overlaps.begin(), g.overlaps.end()), g.overlaps.end());

  // The ground under the bricks that reach it, or settle onto it. On a lattice turned about the
  // vertical the ground lies lower by the height of the lattice's origin; a tilted one stands on
  // no ground.
  for (int i = 0; i < n; ++i) {
    if (g.fixed[size_t(i)]) continue;
    const Brick& brick = a.bricks[size_t(i)];
    double below = 0;  // the frame's origin's height, lattice frame
    if (brick.frame) {
      if (tilted(*brick.frame)) continue;  // its faces are not level: it stands on no ground
      below = to_model(brick, Vec3{0, 0, 0})[1];
    }
    for (const Box& b : shapes[size_t(i)].body) {
      // The table's highest point under the box, and how far above it the box's bottom is.
      const Box mb = model_bounds(brick, b);
      double under = -1e300;
      for (double x : {mb.min[0], mb.max[0]})
        for (double z : {mb.min[2], mb.max[2]}) under = std::max(under, table.at(x, z));
      const double frame_ground = under - below;
      if (b.min[1] <= frame_ground + kSettle) {
        const bool on = std::abs(b.min[1] - frame_ground) <= kTouch;
        Meeting& m = meeting(kGround, i, kPlusY, on ? frame_ground : b.min[1]);
        grow(m.patch, m.has_patch, in_plane(b, 1));
        m.support = true;
      }
    }
  }
  // A turned part's receptacles do not take the baseplate's studs: it rests on them.
  if (ground == GroundMode::Baseplate)
    for (int i = 0; i < n; ++i)
      if (!g.fixed[size_t(i)] && !a.bricks[size_t(i)].frame)
        for (const Connector& r : shapes[size_t(i)].receptacles)
          if (r.direction == kMinusY && on_ground(r.at[1]))
            meeting(kGround, i, kPlusY, ground_y).receptacles.push_back(r.at);

  // Carried parts: grouped where they touch, joined to the bricks they touch, by their bodies
  // and their studs.
  const int carried = int(a.carried.size());
  if (carried > 0) {
    std::vector<std::vector<OrientedBox>> reach = carried_boxes;
    for (int c = 0; c < carried; ++c) {
      const auto studs = world_stud_boxes(a.carried[size_t(c)], kKnobRimRadius);
      reach[size_t(c)].insert(reach[size_t(c)].end(), studs.begin(), studs.end());
    }
    DisjointSets groups(carried);
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
    BoxIndex stud_index;
    std::vector<OrientedBox> stud_boxes;
    std::vector<int> stud_owner;
    for (int i = 0; i < n; ++i)
      for (const Connector& k : shapes[size_t(i)].studs) {
        const OrientedBox b = to_model(a.bricks[size_t(i)], stud_box(k, kKnobRimRadius));
        stud_index.add(b.bounds(), int(stud_boxes.size()));
        stud_boxes.push_back(b);
        stud_owner.push_back(i);
      }
    stud_index.finish();
    std::vector<std::vector<int>> touched(static_cast<size_t>(carried));
    // Per carried part: the analysed parts that reach below its bottom where they touch it, and
    // where (in plan): what can bear its weight.
    std::vector<std::vector<std::pair<int, Rect>>> bearing(static_cast<size_t>(carried));
    for (int c = 0; c < carried; ++c)
      for (int k = 0; k < int(reach[size_t(c)].size()); ++k) {
        // Hinge and turntable halves hold side by side: their fingers or rings engage.
        auto engages_sideways = [&](int brick) {
          return a.carried[size_t(c)].pivots || a.bricks[size_t(brick)].type->pivots;
        };
        auto bears = [&](int brick, const OrientedBox& o, const OrientedBox& m) {
          const Box x = o.bounds(), y = m.bounds();
          if (y.min[1] > carried_bottom[size_t(c)] + kCarriedReach) return;
          const Rect r{std::max(x.min[0], y.min[0]), std::max(x.min[2], y.min[2]),
                       std::min(x.max[0], y.max[0]), std::min(x.max[2], y.max[2])};
          if (r.u1 >= r.u0 && r.v1 >= r.v0) bearing[size_t(c)].emplace_back(brick, r);
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
          if (!touch(o, m, kCarriedReach) || (!engages_sideways(brick) && side_by_side(o, m)))
            return;
          bears(brick, o, m);
          auto& t = touched[size_t(c)];
          if (std::find(t.begin(), t.end(), brick) == t.end()) t.push_back(brick);
        };
        near_in_model(bounds, kCarriedReach,
                      [&](int id) { meets(box_owner[size_t(id)].first, model_box(id)); });
        stud_index.near(bounds, kCarriedReach,
                        [&](int id) { meets(stud_owner[size_t(id)], stud_boxes[size_t(id)]); });
      }
    std::map<int, int> group_of_root;
    std::vector<Vec3> weighted;  // per group: Σ mass · centre
    for (int c = 0; c < carried; ++c) {
      auto [it, inserted] = group_of_root.try_emplace(groups.find(c), int(g.carried_groups.size()));
      if (inserted) {
        g.carried_groups.emplace_back();
        weighted.push_back({0, 0, 0});
      }
      CarriedGroup& group = g.carried_groups[size_t(it->second)];
      group.carried.push_back(c);
      Vec3 centre{0, 0, 0};
      double volume = 0;
      for (const auto& o : carried_boxes[size_t(c)]) {
        const double v = std::max(8 * o.half[0] * o.half[1] * o.half[2], 1e-9);
        for (int ax = 0; ax < 3; ++ax) centre[ax] += v * o.centre[ax];
        volume += v;
      }
      for (const Vec3& p : carried_outline[size_t(c)])
        group.on_ground = group.on_ground || clearance(p) <= kSettle;
      const double m = std::max(a.carried[size_t(c)].mass_g, 1e-9);
      for (int ax = 0; ax < 3; ++ax) weighted[size_t(it->second)][ax] += m * centre[ax] / volume;
      group.mass_g += m;
      for (int brick : touched[size_t(c)]) {
        auto& list = g.fixed[size_t(brick)] ? group.rests_on_fixed : group.joins;
        if (std::find(list.begin(), list.end(), brick) == list.end()) list.push_back(brick);
      }
    }
    for (size_t k = 0; k < g.carried_groups.size(); ++k)
      for (int ax = 0; ax < 3; ++ax)
        g.carried_groups[k].centre[ax] = weighted[k][ax] / g.carried_groups[k].mass_g;
    for (auto& group : g.carried_groups) {
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
        return cx >= r.u0 - kMinFace / 2 && cx <= r.u1 + kMinFace / 2 &&
               cz >= r.v0 - kMinFace / 2 && cz <= r.v1 + kMinFace / 2;
      };
      for (int c : group.carried)
        for (const auto& [brick, r] : bearing[size_t(c)]) {
          if (g.fixed[size_t(brick)]) continue;
          grow(span, any, r);
          const double area = r.area() + (under_centre(r) ? 1e12 : 0);
          if (area > widest) widest = area, group.bearer = brick;
        }
      // Tied to one another by the group, its parts bear it together: the first, where the tree
      // of its joints is rooted, takes its weight.
      if (!group.joins.empty() && (group.bearer < 0 || (group.assumed_joint() && assumed_joints)))
        group.bearer = group.joins.front();
      group.rests = group.on_ground || !group.rests_on_fixed.empty() || (any && under_centre(span));
      if (group.joins.empty() || (!group.on_ground && group.rests_on_fixed.empty())) continue;
      // Where the group stands on the ground or a fixed part, it holds the body it joins like
      // the ground does: it pushes and holds sideways.
      // It stands on its lowest points (a tyre on a strip across its tread): on the table,
      // those nearest it, where it is nearest; on a fixed part, those at its bottom.
      double bottom = 1e300, nearest = 1e300, table_there = 0;
      for (int c : group.carried) {
        bottom = std::min(bottom, carried_bottom[size_t(c)]);
        for (const Vec3& p : carried_outline[size_t(c)])
          if (clearance(p) < nearest) nearest = clearance(p), table_there = table.at(p[0], p[2]);
      }
      Meeting& m = meeting(group.on_ground ? kGround : group.rests_on_fixed.front(), group.bearer,
                           kPlusY, group.on_ground ? table_there : bottom, /*in_model=*/true);
      for (int c : group.carried)
        for (const Vec3& p : carried_outline[size_t(c)])
          if (group.on_ground ? clearance(p) <= kSettle : p[1] <= bottom + kCarriedReach)
            grow(m.patch, m.has_patch, {p[0], p[2], p[0], p[2]});
      if (m.patch.u1 - m.patch.u0 < kMinFace)
        m.patch.u0 -= kMinFace / 2, m.patch.u1 += kMinFace / 2;
      if (m.patch.v1 - m.patch.v0 < kMinFace)
        m.patch.v0 -= kMinFace / 2, m.patch.v1 += kMinFace / 2;
      m.support = true;
    }
  }

  // A stud connection pointing down or to a low side meets the faces there from the other side.
  for (auto& [key, m] : meetings) {
    if (m.receptacles.empty() || sign_of(m.direction) > 0 || m.lower == kGround) continue;
    auto face = meetings.find({m.upper, m.lower, opposite(m.direction), q(m.plane), m.turned});
    if (face == meetings.end() || !face->second.receptacles.empty()) continue;
    if (face->second.has_patch) grow(m.patch, m.has_patch, face->second.patch);
    face->second.has_patch = false;  // one contact for both
  }

  // A contact joins the list and both its parts' lists (the ground has none); returns its index.
  auto add_contact = [&](const Contact& c) {
    const int index = int(g.contacts.size());
    if (c.lower != kGround) g.contacts_of[size_t(c.lower)].push_back(index);
    g.contacts_of[size_t(c.upper)].push_back(index);
    g.contacts.push_back(c);
    return index;
  };

  // Contacts in a fixed order: along the vertical first, by the part above; then across x and z,
  // by the part on the low side.
  std::vector<Meeting*> ordered;
  ordered.reserve(meetings.size());
  for (auto& [key, m] : meetings) {
    if (m.receptacles.empty() && !m.has_patch) continue;
    ordered.push_back(&m);
  }
  auto order_key = [](const Meeting* m) {
    const int axis = axis_of(m->direction);
    const bool positive = sign_of(m->direction) > 0;
    const int primary =
        axis == 1 ? (positive ? m->upper : m->lower) : (positive ? m->lower : m->upper);
    const double f0 = m->has_patch ? m->patch.u0 : 0, s0 = m->has_patch ? m->patch.v0 : 0;
    return std::make_tuple(axis == 1 ? 0 : 1, primary, axis, f0, s0, m->lower, m->upper,
                           m->direction);
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
      c.first_point = uint32_t(g.friction_points.size());
      if (!(ground == GroundMode::Table && c.lower == kGround))
        for (const Vec3& r : rs)
          add_friction_points(receptacles, c.upper, r, opposite(m->direction), g.friction_points);
      c.point_count = uint32_t(g.friction_points.size()) - c.first_point;
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
      for (const Connector& k : shapes[size_t(c.lower)].studs) {
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
  // Technic and hinge joints (docs/physics.md, "Joints"): a pin or an axle of one part on the line
  // of another's hole, within a LDU of it and overlapping it, joins the two; so do two hinge
  // halves' knuckles on one line that overlap or interleave (fingers between fingers), and a bar
  // in a clip. An axle in an axle hole and a locking hinge hold every way; anything else turns
  // about the line, a clip gripping its bar as a friction pin does its hole. Lines
  // along the model's axes are compared in the model's frame, so a hinge half turned on its own
  // lattice meets its other half; others within one lattice.
  std::set<std::pair<int, int>> shaft_joined;
  {
    struct Placed {
      int brick;
      const Shaft* shaft;
      Vec3 a, b;  // in the model's frame, or in the brick's lattice when `frame` >= 0
      int axis, frame;
    };
    using Line = std::tuple<int, int64_t, int64_t, int>;  // axis, the line across it, frame
    auto place = [&](int brick, const Shaft& s) {
      Placed p{
          brick, &s, to_model(a.bricks[size_t(brick)], s.a), to_model(a.bricks[size_t(brick)], s.b),
          0,     -1};
      int moved = 0;
      for (int k = 0; k < 3; ++k)
        if (std::abs(p.a[size_t(k)] - p.b[size_t(k)]) > 1e-3) ++moved, p.axis = k;
      if (moved != 1)  // turned off the model's axes: compared within its own lattice
        p.a = s.a, p.b = s.b, p.axis = s.axis(), p.frame = frame_of(brick);
      return p;
    };
    auto line_of = [](const Placed& p, int64_t du, int64_t dv) {
      const int u = (p.axis + 1) % 3, v = (p.axis + 2) % 3;
      return Line{p.axis, std::llround(p.a[size_t(u)]) + du, std::llround(p.a[size_t(v)]) + dv,
                  p.frame};
    };
    std::map<Line, std::vector<Placed>> receivers;  // holes, knuckles and clips
    std::vector<Placed> inserted;                   // pins, axles, knuckles and bars
    for (int i = 0; i < n; ++i)
      for (const Shaft& s : shapes[size_t(i)].shafts) {
        const Placed p = place(i, s);
        if (s.receives()) receivers[line_of(p, 0, 0)].push_back(p);
        if (!s.receives() || s.knuckle()) inserted.push_back(p);
      }
    struct Fit {
      double lo = 1e300, hi = -1e300;
      bool overlaps = false, holds = false, friction = false;
      int abutting = 0;  // knuckle ends meeting end to end: two when fingers interleave
      const Placed* on = nullptr;
      Line line{};
    };
    std::map<std::pair<int, int>, Fit> fits;  // (part with the hole, part with the shaft)
    if (!receivers.empty())
      for (const Placed& s : inserted)
        for (int64_t du = -1; du <= 1; ++du)
          for (int64_t dv = -1; dv <= 1; ++dv) {
            auto it = receivers.find(line_of(s, du, dv));
            if (it == receivers.end()) continue;
            for (const Placed& r : it->second) {
              const int i = r.brick, j = s.brick;
              if (i == j || (g.fixed[size_t(i)] && g.fixed[size_t(j)])) continue;
              if (!Shaft::fits(*s.shaft, *r.shaft) || (s.shaft->knuckle() && i > j)) continue;
              const int axis = s.axis, u = (axis + 1) % 3, v = (axis + 2) % 3;
              if (std::hypot(r.a[size_t(u)] - s.a[size_t(u)], r.a[size_t(v)] - s.a[size_t(v)]) >
                  kCarriedReach)
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
                        (kind == Shaft::Kind::LockingKnuckle && other == kind) ||
                        (knuckles && second_line);
              f.line = line;
              f.friction =
                  f.friction || kind == Shaft::Kind::FrictionPin || other == Shaft::Kind::Clip;
              f.on = &r;
            }
          }
    for (auto& [pair, f] : fits) {
      // Two hinge halves end to end in a row meet at one end; interleaved fingers at two.
      if (!f.overlaps && f.abutting < 2) continue;
      const auto [i, j] = pair;
      Contact c;
      c.lower = g.fixed[size_t(j)] ? j : i;
      c.upper = g.fixed[size_t(j)] ? i : j;
      c.joint = true;
      c.joint_kind = f.holds ? Contact::Kind::Holds : Contact::Kind::Turns;
      c.joint_friction = f.friction;
      Vec3 mid = f.on->a, axis{0, 0, 0};
      mid[size_t(f.on->axis)] = (f.lo + f.hi) / 2;
      axis[size_t(f.on->axis)] = 1;
      const Brick& on = a.bricks[size_t(f.on->brick)];
      c.joint_point = f.on->frame < 0 ? mid : to_model(on, mid);
      c.joint_axis = f.on->frame < 0 ? axis : to_model_direction(on, axis);
      g.shaft_joints.push_back(add_contact(c));
      shaft_joined.insert({std::min(i, j), std::max(i, j)});
    }
  }
  // Assumed-rigid joints, after every other contact: each group ties the bricks it joins along
  // the shortest links between their centres (a tree of joints is as rigid as one body). Merged
  // into one body, those bricks made rows dense and the interior point method stalled; a star
  // from one brick did too. A tree keeps each brick's joints few and their lever arms short.
  std::vector<Vec3> centre(static_cast<size_t>(n));
  for (const CarriedGroup& group : g.carried_groups) {
    const auto& joins = group.joins;
    if (joins.size() < 2 || !assumed_joints) continue;
    for (int b : joins) centre[size_t(b)] = body_centre(a.bricks[size_t(b)]);
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
  // Where parts of two lattices touch (a turned stand on its base), or two hinge or turntable
  // halves touch without a line they share (a hinge whose fingers' primitives are not
  // cylinders), nothing tells how they hold: they are joined as a carried part joins what it
  // touches (README "What it analyses").
  auto pivots = [&](int i) { return a.bricks[size_t(i)].type->pivots; };
  bool any_pivot = false;
  for (int i = 0; i < n && !any_pivot; ++i) any_pivot = pivots(i);
  // Legolize's bricks are neither: its many analyses skip this.
  if (assumed_joints && (any_turned || any_pivot)) {
    std::set<std::pair<int, int>> lattice_pairs, pivot_pairs, snapped;
    if (any_pivot)
      for (const Contact& c : g.contacts)
        if (c.snap()) snapped.insert({std::min(c.lower, c.upper), std::max(c.lower, c.upper)});
    for (int id = 0; id < int(box_owner.size()); ++id) {
      const int i = box_owner[size_t(id)].first;
      if (!a.bricks[size_t(i)].frame && !pivots(i)) continue;
      const OrientedBox o = model_box(id);
      near_in_model(o.bounds(), kCarriedReach, [&](int other) {
        const int j = box_owner[size_t(other)].first;
        const std::pair<int, int> pair{std::min(i, j), std::max(i, j)};
        if (i == j || (g.fixed[size_t(i)] && g.fixed[size_t(j)])) return;
        const bool across = frame_of(j) != frame_of(i) && a.bricks[size_t(i)].frame;
        // Once per pair across lattices: from the turned one when only one is, else from the
        // lower frame id.
        if (across && a.bricks[size_t(j)].frame && frame_of(j) < frame_of(i)) return;
        // Two halves of one hinge are two parts: the same part side by side in a row is none.
        const bool halves =
            pivots(i) && pivots(j) && a.bricks[size_t(i)].type != a.bricks[size_t(j)].type;
        if (!across && !halves) return;
        // Snapped to each other, they hold by their studs; joined, by their joint.
        if (snapped_across.count(pair) || shaft_joined.count(pair)) return;
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
      c.lower = g.fixed[size_t(y)] ? y : x;
      c.upper = g.fixed[size_t(y)] ? x : y;
      c.joint = true;
      const Vec3 cx = body_centre(a.bricks[size_t(x)]), cy = body_centre(a.bricks[size_t(y)]);
      for (int ax = 0; ax < 3; ++ax)
        c.joint_point[size_t(ax)] = (cx[size_t(ax)] + cy[size_t(ax)]) / 2;
      into.push_back(add_contact(c));
    };
    for (const auto& pair : lattice_pairs) join(pair, g.lattice_joints);
    for (const auto& pair : pivot_pairs) join(pair, g.pivot_joints);
  }
  return g;
}

}  // namespace lego::physics
