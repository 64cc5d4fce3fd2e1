// Studs in receptacles: of one lattice, along any axis; of two lattices, upright, where the model
// puts them; and where on its receptacle's wall each stud presses.
#include <algorithm>
#include <cmath>

#include "physics/contact_graph_builder.h"
#include "physics/knob_grip.h"

namespace lego::physics {

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

// Studs in receptacles of one lattice, along any axis.
void ContactGraphBuilder::engage_studs() {
  for (int l = 0; l < n_; ++l) {
    check_time(l);
    for (const Connector& s : shapes_[size_t(l)].studs)
      for (int e = receptacles_.find(s.at, opposite(s.direction)); e >= 0;
           e = receptacles_[e].next) {
        const int u = receptacles_[e].brick;
        if (u == l || (g_.fixed[size_t(l)] && g_.fixed[size_t(u)]) || frame_of(u) != frame_of(l))
          continue;
        meeting(l, u, s.direction, s.at[size_t(axis_of(s.direction))])
            .receptacles.push_back(receptacles_[e].at);
      }
  }
}

// Studs in receptacles of another lattice, both upright (docs/what-it-analyses.md, turned
// lattices): a stud in a receptacle is a connection however the two parts are turned about it
// (the water tower's ring of 1 x 3 bricks, each turned on a stud of the one below). Found where
// the model puts them: the corpus places such rings by eye, a stud up to 3 LDU from the
// receptacle it is in, so within the receptacle's cell (kStudInCellLdu). Two parts joined by
// more than one stud cannot be turned against each other: their studs must then be off their
// receptacles by one common shift (within the LDU a part placed by eye strays), else none of
// them is in a receptacle.
void ContactGraphBuilder::engage_studs_across_lattices() {
  if (!any_turned_) return;
  // Upright parts of turned lattices, and the parts of other lattices within reach of them.
  std::vector<char> across(size_t(n_), 0);
  for (int i = 0; i < n_; ++i) {
    const Brick& b = a_.bricks[size_t(i)];
    if (!b.frame || tilted(*b.frame)) continue;
    across[size_t(i)] = 1;
    for (const Box& box : shapes_[size_t(i)].body)
      near_in_model(model_bounds(b, box), kCarriedReach, [&](int id) {
        const int j = owner(id);
        const Brick& other = a_.bricks[size_t(j)];
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
  for (int i = 0; i < n_; ++i)
    if (across[size_t(i)])
      for (const Connector& r : shapes_[size_t(i)].receptacles)
        if (vertical(r)) {
          const Vec3 m = to_model(a_.bricks[size_t(i)], r.at);
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
  for (int l = 0; l < n_; ++l) {
    if (!across[size_t(l)]) continue;
    for (const Connector& k : shapes_[size_t(l)].studs) {
      if (!vertical(k)) continue;
      const Vec3 m = to_model(a_.bricks[size_t(l)], k.at);
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
                  (g_.fixed[size_t(l)] && g_.fixed[size_t(u)]))
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
    snapped_across_.emplace(std::min(engaged[first].lower, engaged[first].upper),
                            std::max(engaged[first].lower, engaged[first].upper));
  }
}

}  // namespace lego::physics
