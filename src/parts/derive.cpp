#include "parts/derive.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "core/lattice.h"
#include "core/text.h"

namespace lego::parts {
namespace {

constexpr double kPitch = kLduPerStud;
// A stud is 6 LDU in radius and 4 high; a receptacle must leave it this much room.
constexpr double kStudRoom = 5.5, kStudDepth = 3.5;
// The walls, pins or tubes around a receptacle are within this of its axis.
constexpr double kEnclosure = 10.5;
// How far above a receptacle's opening its walls are looked for.
constexpr double kRimHeight = 2;
// A tube's bore holds a stud (6 LDU in radius) all round.
constexpr double kBoreRadius = 6.5;
constexpr double kEps = 1e-6;

using Polygon = std::vector<Vec3>;

// Keeps the part of `poly` where coordinate `axis` is >= bound (above) or <= bound.
void clip(Polygon& poly, int axis, double bound, bool keep_above) {
  if (poly.empty()) return;
  Polygon out;
  out.reserve(poly.size() + 2);
  auto inside = [&](const Vec3& p) {
    return keep_above ? p[size_t(axis)] >= bound - kEps : p[size_t(axis)] <= bound + kEps;
  };
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % poly.size()];
    const bool ia = inside(a), ib = inside(b);
    if (ia) out.push_back(a);
    if (ia != ib) {
      const double t = (bound - a[size_t(axis)]) / (b[size_t(axis)] - a[size_t(axis)]);
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[size_t(k)] = a[size_t(k)] + t * (b[size_t(k)] - a[size_t(k)]);
      out.push_back(p);
    }
  }
  poly = std::move(out);
}

Polygon clipped(const Triangle& t, double x0, double x1, double z0, double z1) {
  Polygon p{t.p[0], t.p[1], t.p[2]};
  clip(p, 0, x0, true);
  clip(p, 0, x1, false);
  clip(p, 2, z0, true);
  clip(p, 2, z1, false);
  return p;
}

Box face_bounds(const PartGeometry& g) {
  Box b{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  for (const Triangle& t : g.faces)
    for (const Vec3& p : t.p)
      for (int a = 0; a < 3; ++a) {
        b.min[size_t(a)] = std::min(b.min[size_t(a)], p[size_t(a)]);
        b.max[size_t(a)] = std::max(b.max[size_t(a)], p[size_t(a)]);
      }
  return b;
}

// Triangles by the cells of a grid over x and z that their bounds reach.
class FaceGrid {
 public:
  FaceGrid(const PartGeometry& g, const Box& bounds, double cell)
      : g_(g), x0_(bounds.min[0]), z0_(bounds.min[2]), cell_(cell) {
    nx_ = std::max(1, int(std::ceil((bounds.max[0] - x0_) / cell)) + 1);
    nz_ = std::max(1, int(std::ceil((bounds.max[2] - z0_) / cell)) + 1);
    cells_.resize(size_t(nx_) * size_t(nz_));
    for (int i = 0; i < int(g.faces.size()); ++i) {
      const Triangle& t = g.faces[size_t(i)];
      double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
      for (const Vec3& p : t.p) {
        lo[0] = std::min(lo[0], p[0]), hi[0] = std::max(hi[0], p[0]);
        lo[1] = std::min(lo[1], p[2]), hi[1] = std::max(hi[1], p[2]);
      }
      for (int x = column(lo[0], x0_, nx_); x <= column(hi[0], x0_, nx_); ++x)
        for (int z = column(lo[1], z0_, nz_); z <= column(hi[1], z0_, nz_); ++z)
          cells_[size_t(x) * size_t(nz_) + size_t(z)].push_back(i);
    }
  }
  // The faces whose bounds may reach the rectangle, each once.
  std::vector<int> near(double x_lo, double x_hi, double z_lo, double z_hi) const {
    std::vector<int> out;
    for (int x = column(x_lo, x0_, nx_); x <= column(x_hi, x0_, nx_); ++x)
      for (int z = column(z_lo, z0_, nz_); z <= column(z_hi, z0_, nz_); ++z)
        for (int i : cells_[size_t(x) * size_t(nz_) + size_t(z)]) out.push_back(i);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  const PartGeometry& g_;
  double x0_, z0_, cell_;
  int nx_ = 1, nz_ = 1;
  std::vector<std::vector<int>> cells_;
  int column(double v, double origin, int n) const {
    return std::clamp(int(std::floor((v - origin) / cell_)), 0, n - 1);
  }
};

// Distance in the x-z plane from (x, z) to a polygon (0 inside it).
double distance_xz(const Polygon& poly, double x, double z) {
  if (poly.empty()) return 1e300;
  double best = 1e300;
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const double ax = poly[j][0], az = poly[j][2], bx = poly[i][0], bz = poly[i][2];
    const double dx = bx - ax, dz = bz - az, length2 = dx * dx + dz * dz;
    double t = length2 > 0 ? ((x - ax) * dx + (z - az) * dz) / length2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    best = std::min(best, std::hypot(ax + t * dx - x, az + t * dz - z));
    if ((az > z) != (bz > z) && x < ax + (z - az) / (bz - az) * (bx - ax)) inside = !inside;
  }
  return inside && poly.size() >= 3 ? 0 : best;
}

// Where a ray from (x, z) along (dx, dz) first meets the polygon's outline, or infinity.
double ray_hit(const Polygon& poly, double x, double z, double dx, double dz) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const double ax = poly[j][0], az = poly[j][2], ex = poly[i][0] - ax, ez = poly[i][2] - az;
    const double denom = dx * ez - dz * ex;
    if (std::abs(denom) < 1e-12) continue;
    const double t = ((ax - x) * ez - (az - z) * ex) / denom;
    const double s = ((ax - x) * dz - (az - z) * dx) / denom;
    if (t >= 0 && s >= -kEps && s <= 1 + kEps) best = std::min(best, t);
  }
  return best;
}

Polygon slab(const Triangle& t, double y0, double y1) {
  Polygon p{t.p[0], t.p[1], t.p[2]};
  clip(p, 1, y0, true);
  clip(p, 1, y1, false);
  return p;
}

double snap(double v) {
  return std::round(v * 8) / 8;
}

// Parts whose connections are not studs in receptacles, by what the library calls them: LDraw
// names a part by its kind first ("Hinge Plate 1 x 2 ...", "Wheel 11 x 12 ..."), while "Plate
// 1 x 4 with 2 Wheel Pins" is a plate.
std::string first_word(const PartGeometry& g) {
  const std::string_view title = without_title_marks(g.title);
  return std::string(title.substr(0, title.find(' ')));
}

bool minifigure(const PartGeometry& g) {
  return g.category.starts_with("Minifig") || first_word(g) == "Minifig";
}

std::optional<PartRole> carried_by_name(const PartGeometry& g) {
  const std::string first = first_word(g);
  const std::string_view title = without_title_marks(g.title);
  if (minifigure(g)) return PartRole::MinifigurePart;
  if (first == "Hinge") return PartRole::HingeWithoutCells;
  if (first == "Turntable") return PartRole::Turntable;
  if (first == "Door" && !title.starts_with("Door Frame")) return PartRole::Door;
  if (first == "Wheel" || first == "Tyre" || first == "Tire") return PartRole::WheelWithoutAxleLine;
  return std::nullopt;
}

// The line a shaft lies on: its axis and where it crosses the other two, on a quarter-LDU grid.
using ShaftLine = std::tuple<int, double, double>;
ShaftLine line_of(const Shaft& s) {
  const int axis = s.axis();
  auto grid = [](double x) { return std::round(x * 4) / 4; };
  return {axis, grid(s.a[size_t((axis + 1) % 3)]), grid(s.a[size_t((axis + 2) % 3)])};
}

// The part's Technic connections as whole shafts: the pieces a primitive draws on one line
// (a pin's two halves, a hole's end rings) joined, where they touch or, for holes, where no more
// than a stud's width lies between them.
std::vector<Shaft> joined_shafts(std::vector<Shaft> drawn) {
  struct Key {
    Shaft::Kind kind;
    int axis;
    double u, v, lo, hi;
  };
  std::vector<Key> keys;
  for (const Shaft& s : drawn) {
    const auto [axis, u, v] = line_of(s);
    keys.push_back({s.kind, axis, u, v, std::min(s.a[size_t(axis)], s.b[size_t(axis)]),
                    std::max(s.a[size_t(axis)], s.b[size_t(axis)])});
  }
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return std::tie(x.kind, x.axis, x.u, x.v, x.lo) < std::tie(y.kind, y.axis, y.u, y.v, y.lo);
  });
  std::vector<Shaft> out;
  for (size_t i = 0; i < keys.size();) {
    Key k = keys[i];
    const bool hole = k.kind == Shaft::Kind::PinHole || k.kind == Shaft::Kind::AxleHole;
    size_t j = i + 1;
    for (; j < keys.size() && keys[j].kind == k.kind && keys[j].axis == k.axis &&
           keys[j].u == k.u && keys[j].v == k.v && keys[j].lo <= k.hi + (hole ? kPitch : kEps);
         ++j)
      k.hi = std::max(k.hi, keys[j].hi);
    Shaft s;
    s.kind = k.kind;
    s.a[size_t(k.axis)] = k.lo, s.b[size_t(k.axis)] = k.hi;
    s.a[size_t((k.axis + 1) % 3)] = s.b[size_t((k.axis + 1) % 3)] = k.u;
    s.a[size_t((k.axis + 2) % 3)] = s.b[size_t((k.axis + 2) % 3)] = k.v;
    out.push_back(s);
    i = j;
  }
  return out;
}

// A hinge or turntable half turns about a line its round surfaces share with its other half: its
// knuckles are its cylinder primitives, on every line they cover 2 LDU or more of (a hinge
// plate's finger is rounded on the line of its pin and on another; which one is the pin's, only
// the other half tells: physics/graph_joints.cpp joins two halves on a line they share). A locking
// hinge clicks in place: its knuckles hold.
std::vector<Shaft> knuckles(const PartGeometry& g) {
  const bool locking = g.title.find("Locking") != std::string::npos;
  const auto kind = locking ? Shaft::Kind::LockingKnuckle : Shaft::Kind::Knuckle;
  std::map<ShaftLine, double> cover;
  for (const Round& r : g.rounds) {
    const Shaft s{kind, r.a, r.b};
    cover[line_of(s)] += std::abs(s.a[size_t(s.axis())] - s.b[size_t(s.axis())]);
  }
  std::vector<Shaft> kept;
  for (const Round& r : g.rounds)
    if (const Shaft s{kind, r.a, r.b}; cover[line_of(s)] >= 2)  // slivers are no finger
      kept.push_back(s);
  return joined_shafts(std::move(kept));
}

// A bar is 3.2 mm across: its round surfaces are 4 LDU in radius and go all the way round its line
// (a handle's two halves together). A clip grips a bar: the round surfaces of that radius a clip
// primitive (clip*.dat) draws, half a turn or more of them on the line.
constexpr double kBarRadius = 4, kBarRadiusTolerance = 0.5;
std::vector<Shaft> bars_and_clips(const PartGeometry& g) {
  std::vector<Shaft> out;
  for (const bool clip : {false, true}) {
    const auto kind = clip ? Shaft::Kind::Clip : Shaft::Kind::Bar;
    const double least_turn = clip ? 0.5 : 0.9;
    std::vector<Shaft> pieces;
    std::vector<double> turns;
    for (const Round& r : g.rounds)
      if (r.clip == clip && std::abs(r.radius - kBarRadius) <= kBarRadiusTolerance) {
        pieces.push_back({kind, r.a, r.b});
        turns.push_back(r.turn);
      }
    for (const Shaft& whole : joined_shafts(pieces)) {
      // How much of a turn the pieces on the joined length draw, on average along it.
      const int axis = whole.axis();
      const double lo = std::min(whole.a[size_t(axis)], whole.b[size_t(axis)]);
      const double hi = std::max(whole.a[size_t(axis)], whole.b[size_t(axis)]);
      double drawn = 0;
      for (size_t k = 0; k < pieces.size(); ++k) {
        const Shaft& p = pieces[k];
        if (line_of(p) != line_of(whole)) continue;
        const double p_lo = std::min(p.a[size_t(axis)], p.b[size_t(axis)]);
        const double p_hi = std::max(p.a[size_t(axis)], p.b[size_t(axis)]);
        drawn += turns[k] * std::max(0.0, std::min(hi, p_hi) - std::max(lo, p_lo));
      }
      if (hi - lo >= 1 && drawn >= least_turn * (hi - lo)) out.push_back(whole);
    }
  }
  return out;
}

enum class Rolling { No, Wheel, Tyre };
Rolling rolling(const PartGeometry& g) {
  const std::string first = first_word(g);
  if (first == "Wheel") return Rolling::Wheel;
  if (first == "Tyre" || first == "Tire") return Rolling::Tyre;
  return Rolling::No;
}

// The line a wheel or a tyre turns about: the one its round surfaces are drawn on most (their
// length times the share of a turn they draw, times their radius: the tread outweighs a hub's
// details). Drawn without cylinder primitives (a tread of segments turned about the axle), a part
// round about an axis is as wide as high across it: the axis is the one whose two others agree,
// the line through the middle. None for a part round every way or no way.
std::optional<ShaftLine> turning_line(const PartGeometry& g, const Box& bounds) {
  std::map<ShaftLine, double> weight;
  for (const Round& r : g.rounds) {
    const Shaft s{Shaft::Kind::Knuckle, r.a, r.b};
    weight[line_of(s)] +=
        r.turn * r.radius * std::abs(s.a[size_t(s.axis())] - s.b[size_t(s.axis())]);
  }
  if (!weight.empty())
    return std::max_element(weight.begin(), weight.end(),
                            [](const auto& x, const auto& y) { return x.second < y.second; })
        ->first;
  std::optional<ShaftLine> line;
  for (int k = 0; k < 3; ++k) {
    const size_t u = size_t(k + 1) % 3, v = size_t(k + 2) % 3;
    const double du = bounds.max[u] - bounds.min[u], dv = bounds.max[v] - bounds.min[v];
    if (std::abs(du - dv) > 1 || du <= bounds.max[size_t(k)] - bounds.min[size_t(k)]) continue;
    if (line) return std::nullopt;
    Shaft middle{Shaft::Kind::Knuckle, {0, 0, 0}, {0, 0, 0}};
    middle.b[size_t(k)] = 1;
    for (size_t a : {u, v}) middle.a[a] = middle.b[a] = (bounds.min[a] + bounds.max[a]) / 2;
    line = line_of(middle);
  }
  return line;
}

// On its turning line, across its whole width, a wheel has its hub (where a wheel pin, a pin or
// an axle turns, unless its file draws a Technic hole there) and its rim; a tyre takes a rim.
// None where the line is not found.
std::vector<Shaft> axle_line(const PartGeometry& g, Rolling kind, const std::vector<Shaft>& drawn,
                             const Box& bounds) {
  const std::optional<ShaftLine> line = turning_line(g, bounds);
  if (!line) return {};
  const auto [axis, u, v] = *line;
  Shaft across;
  across.a[size_t(axis)] = bounds.min[size_t(axis)];
  across.b[size_t(axis)] = bounds.max[size_t(axis)];
  across.a[size_t((axis + 1) % 3)] = across.b[size_t((axis + 1) % 3)] = u;
  across.a[size_t((axis + 2) % 3)] = across.b[size_t((axis + 2) % 3)] = v;
  std::vector<Shaft> out;
  auto with = [&](Shaft::Kind kind) {
    Shaft s = across;
    s.kind = kind;
    out.push_back(s);
  };
  if (kind == Rolling::Tyre) {
    with(Shaft::Kind::Tyre);
    return out;
  }
  with(Shaft::Kind::Rim);
  const bool technic_hub = std::any_of(
      drawn.begin(), drawn.end(), [&](const Shaft& s) { return s.hole() && line_of(s) == *line; });
  if (!technic_hub) with(Shaft::Kind::Hub);
  return out;
}

}  // namespace

std::vector<Box> body_boxes(const PartGeometry& g, const std::optional<Vec3>& cell_centre) {
  if (g.faces.empty()) return {};
  const Box bb = face_bounds(g);
  // Columns follow the part's cells where it has any, else start at its side.
  double x0 = bb.min[0], z0 = bb.min[2];
  if (cell_centre) {
    x0 = (*cell_centre)[0] - kPitch / 2 -
         kPitch * std::ceil(((*cell_centre)[0] - kPitch / 2 - bb.min[0]) / kPitch - 1e-6);
    z0 = (*cell_centre)[2] - kPitch / 2 -
         kPitch * std::ceil(((*cell_centre)[2] - kPitch / 2 - bb.min[2]) / kPitch - 1e-6);
  }
  const int nx = std::max(1, int(std::ceil((bb.max[0] - x0) / kPitch - 1e-6)));
  const int nz = std::max(1, int(std::ceil((bb.max[2] - z0) / kPitch - 1e-6)));
  if (double(nx) * nz > 65536) return {bb};  // too wide to cut into columns: its bounds
  auto edge_x = [&](int i) { return std::clamp(x0 + kPitch * i, bb.min[0], bb.max[0]); };
  auto edge_z = [&](int k) { return std::clamp(z0 + kPitch * k, bb.min[2], bb.max[2]); };
  std::vector<double> lo(size_t(nx) * nz, 1e300), hi(size_t(nx) * nz, -1e300);
  // A column takes the faces inside it, not those on its border: the wall between two columns
  // belongs to neither, so an empty corner of an L-shaped part stays empty.
  constexpr double kInset = 0.5;
  for (const Triangle& t : g.faces) {
    double x_lo = 1e300, x_hi = -1e300, z_lo = 1e300, z_hi = -1e300;
    for (const Vec3& p : t.p) {
      x_lo = std::min(x_lo, p[0]), x_hi = std::max(x_hi, p[0]);
      z_lo = std::min(z_lo, p[2]), z_hi = std::max(z_hi, p[2]);
    }
    const int i0 = std::clamp(int(std::floor((x_lo - x0) / kPitch)), 0, nx - 1);
    const int i1 = std::clamp(int(std::floor((x_hi - x0) / kPitch)), 0, nx - 1);
    const int k0 = std::clamp(int(std::floor((z_lo - z0) / kPitch)), 0, nz - 1);
    const int k1 = std::clamp(int(std::floor((z_hi - z0) / kPitch)), 0, nz - 1);
    for (int i = i0; i <= i1; ++i)
      for (int k = k0; k <= k1; ++k) {
        const double cx0 = edge_x(i), cx1 = edge_x(i + 1), cz0 = edge_z(k), cz1 = edge_z(k + 1);
        if (cx1 - cx0 < 1e-9 || cz1 - cz0 < 1e-9) continue;
        const double ix = std::min(kInset, (cx1 - cx0) / 4), iz = std::min(kInset, (cz1 - cz0) / 4);
        const Polygon p = clipped(t, cx0 + ix, cx1 - ix, cz0 + iz, cz1 - iz);
        for (const Vec3& v : p) {
          lo[size_t(i) * nz + k] = std::min(lo[size_t(i) * nz + k], v[1]);
          hi[size_t(i) * nz + k] = std::max(hi[size_t(i) * nz + k], v[1]);
        }
      }
  }
  // Runs along x of equal extent, then runs of those along z.
  struct Run {
    int i0, i1, k0, k1;
    double y0, y1;
  };
  std::vector<Run> runs, open;
  auto same = [](double a, double b) { return std::abs(a - b) < 0.01; };
  for (int k = 0; k < nz; ++k) {
    std::vector<Run> row;
    for (int i = 0; i < nx; ++i) {
      const double y0 = lo[size_t(i) * nz + k], y1 = hi[size_t(i) * nz + k];
      if (y1 - y0 < 0.01) continue;  // nothing, or a sheet with no thickness
      if (!row.empty() && row.back().i1 == i && same(row.back().y0, y0) && same(row.back().y1, y1))
        row.back().i1 = i + 1;
      else
        row.push_back({i, i + 1, k, k + 1, y0, y1});
    }
    std::vector<Run> next;
    for (Run r : row) {
      auto it = std::find_if(open.begin(), open.end(), [&](const Run& o) {
        return o.i0 == r.i0 && o.i1 == r.i1 && o.k1 == k && same(o.y0, r.y0) && same(o.y1, r.y1);
      });
      if (it != open.end()) {
        r.k0 = it->k0;
        open.erase(it);
      }
      next.push_back(r);
    }
    runs.insert(runs.end(), open.begin(), open.end());
    open = std::move(next);
  }
  runs.insert(runs.end(), open.begin(), open.end());
  std::vector<Box> out;
  for (const Run& r : runs)
    out.push_back({{edge_x(r.i0), r.y0, edge_z(r.k0)}, {edge_x(r.i1), r.y1, edge_z(r.k1)}});
  std::sort(out.begin(), out.end(), [](const Box& a, const Box& b) {
    return std::tie(a.min[2], a.min[0], a.min[1]) < std::tie(b.min[2], b.min[0], b.min[1]);
  });
  return out;
}

Receptacles receptacles(const PartGeometry& g) {
  if (g.faces.empty()) return {};
  const Box bb = face_bounds(g);
  if ((bb.max[0] - bb.min[0]) * (bb.max[2] - bb.min[2]) > 4e6) return {};  // 100 x 100 studs
  const FaceGrid grid(g, bb, kPitch / 2);
  struct Candidate {
    double x, z, plane;
    int phase;
    bool bore;
  };
  std::vector<Candidate> found;
  const double half = kPitch / 2;
  // Stud centres lie on multiples of half a stud in a part's own frame: try every one under it.
  const double x_first = std::ceil((bb.min[0] + half - kEps) / half) * half;
  const double z_first = std::ceil((bb.min[2] + half - kEps) / half) * half;
  for (int i = 0; x_first + half * i <= bb.max[0] - half + kEps; ++i)
    for (int k = 0; z_first + half * k <= bb.max[2] - half + kEps; ++k) {
      const double x = x_first + half * i, z = z_first + half * k;
      const auto near = grid.near(x - half - 1, x + half + 1, z - half - 1, z + half + 1);
      // The bottom of the part here: the lowest point of what lies over this cell. A face that
      // only meets its border (the end of a wheel pin beside a plate's cell) is a neighbour's.
      auto on_border = [&](const Polygon& p) {
        for (const auto& [axis, at] : {std::pair(0, x - half), std::pair(0, x + half),
                                       std::pair(2, z - half), std::pair(2, z + half)})
          if (std::all_of(p.begin(), p.end(),
                          [&](const Vec3& v) { return std::abs(v[size_t(axis)] - at) < kEps; }))
            return true;
        return false;
      };
      double plane = -1e300;
      for (int f : near)
        if (const Polygon p = clipped(g.faces[size_t(f)], x - half, x + half, z - half, z + half);
            !on_border(p))
          for (const Vec3& v : p) plane = std::max(plane, v[1]);
      if (plane < -1e299) continue;
      bool blocked = false;
      for (int f : near) {
        const Polygon p = slab(g.faces[size_t(f)], plane - kStudDepth, plane + 0.01);
        if (!p.empty() && distance_xz(p, x, z) < kStudRoom) {
          blocked = true;
          break;
        }
      }
      if (blocked) continue;
      // The part covers the cell from above (an L-shaped part's open corner is not a cell) ...
      bool covered = false;
      for (int f : near) {
        const Polygon p = slab(g.faces[size_t(f)], -1e300, plane - kStudDepth + 0.01);
        if (!p.empty() && distance_xz(p, x, z) < kStudRoom) {
          covered = true;
          break;
        }
      }
      if (!covered) continue;
      // ... and stands around it at its bottom: walls, pins or tubes on two sides at least (the
      // rising underside of an inverted slope is not a cell).
      static const double kSpokes[8][2] = {{1, 0},
                                           {-1, 0},
                                           {0, 1},
                                           {0, -1},
                                           {M_SQRT1_2, M_SQRT1_2},
                                           {M_SQRT1_2, -M_SQRT1_2},
                                           {-M_SQRT1_2, M_SQRT1_2},
                                           {-M_SQRT1_2, -M_SQRT1_2}};
      std::vector<Polygon> rim;  // the faces at its bottom, clipped once for all eight spokes
      for (int f : near)
        if (Polygon p = slab(g.faces[size_t(f)], plane - kRimHeight, plane + 0.01); p.size() >= 2)
          rim.push_back(std::move(p));
      int enclosed = 0, held = 0;
      for (const auto& spoke : kSpokes) {
        // The nearest wall matters only while the cell may still be a bore (held on every spoke).
        const double enough = held == int(&spoke - kSpokes) ? kBoreRadius : kEnclosure;
        double reach = std::numeric_limits<double>::infinity();
        for (const Polygon& p : rim)
          if ((reach = std::min(reach, ray_hit(p, x, z, spoke[0], spoke[1]))) <= enough) break;
        enclosed += reach <= kEnclosure;
        held += reach <= kBoreRadius;
      }
      const int phase = int(std::lround(x / half)) % 2 != 0 ? 2 : 0;
      if (enclosed >= 2)
        found.push_back({x, z, plane, phase + (int(std::lround(z / half)) % 2 != 0), held == 8});
    }
  // One lattice of receptacles: the phase most of them share (the part's own cells first).
  int count[4] = {0, 0, 0, 0};
  for (const auto& c : found) ++count[c.phase];
  int phase = 0;
  for (int p = 1; p < 4; ++p)
    if (count[p] > count[phase]) phase = p;
  Receptacles out;
  for (const auto& c : found) {
    const Connector r{{snap(c.x), snap(c.plane), snap(c.z)}, kPlusY};
    if (c.phase == phase)
      out.cells.push_back(r);
    else if (c.phase == (phase ^ 3) && c.bore)
      out.bores.push_back(r);
  }
  return out;
}

std::vector<Vec3> outline(const PartGeometry& g) {
  std::vector<Vec3> out;
  if (g.faces.empty()) return out;
  for (int dx = -2; dx <= 2; ++dx)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dz = -2; dz <= 2; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const Vec3* best = &g.faces.front().p[0];
        double reach = -1e300;
        for (const Triangle& t : g.faces)
          for (const Vec3& v : t.p)
            if (const double r = dx * v[0] + dy * v[1] + dz * v[2]; r > reach) reach = r, best = &v;
        const Vec3 p{snap(best->at(0)), snap(best->at(1)), snap(best->at(2))};
        if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
      }
  return out;
}

double estimated_density(const BrickCatalog& catalog) {
  double mass = 0, volume = 0;
  for (const auto& t : catalog.types())
    if (t.mass_source.starts_with("paper")) {
      mass += t.mass_g;
      volume += double(t.length) * t.width * t.height * kLduPerStud * kLduPerStud * kLduPerPlate;
    }
  return volume > 0 ? mass / volume : 0;
}

PartKnowledge derive_part(const std::string& part, const PartGeometry& g,
                          const BrickCatalog& catalog) {
  PartKnowledge k;
  BrickType& t = k.type;
  t.part = part;
  t.name = g.title;
  t.kind = g.category;
  for (const Connector& s : g.studs)
    t.shape.studs.push_back({{snap(s.at[0]), snap(s.at[1]), snap(s.at[2])}, s.direction});
  Receptacles found = receptacles(g);
  t.shape.receptacles = std::move(found.cells);
  t.shape.bores = std::move(found.bores);
  t.shape.shafts = joined_shafts(g.shafts);
  std::optional<Vec3> cell;
  for (const Connector& s : t.shape.studs)
    if (s.direction == kMinusY) cell = s.at;
  if (!t.shape.receptacles.empty()) cell = t.shape.receptacles.front().at;
  t.shape.body = body_boxes(g, cell);
  t.shape.outline = outline(g);
  t.baseplate = g.category == "Baseplate" || g.title.starts_with("Baseplate");
  t.pivots = first_word(g) == "Hinge" || first_word(g) == "Turntable";
  // A hinge's round surfaces are its knuckles (its pin among them), and nothing else; a wheel's
  // and a tyre's are their axle line (a wheel's hub is no bar).
  const Rolling rolls = rolling(g);
  const std::vector<Shaft> rounds = t.pivots ? knuckles(g)
                                    : rolls != Rolling::No
                                        ? axle_line(g, rolls, t.shape.shafts, face_bounds(g))
                                        : bars_and_clips(g);
  t.rolls = rolls != Rolling::No && !rounds.empty();
  t.shape.shafts.insert(t.shape.shafts.end(), rounds.begin(), rounds.end());
  if (t.shape.body.empty()) {
    // Nothing but studs: a box around them keeps its weight somewhere.
    k.carried = PartRole::DrawsNoBody;
    Box b{{-10, 0, -10}, {10, 4, 10}};
    t.shape.body = {b};
  }
  const Box bounds = t.shape.bounds();
  t.length = std::max(1, int(std::lround((bounds.max[0] - bounds.min[0]) / kLduPerStud)));
  t.width = std::max(1, int(std::lround((bounds.max[2] - bounds.min[2]) / kLduPerStud)));
  t.height = std::max(1, int(std::lround((bounds.max[1] - bounds.min[1]) / kLduPerPlate)));
  t.has_knobs = !t.shape.studs.empty();
  if (const BrickType* known = catalog.find(part)) {
    t.mass_g = known->mass_g;
    t.mass_source = known->mass_source;
  } else {
    const double density = estimated_density(catalog);
    t.mass_g = std::max(density * t.shape.body_volume(), 0.01);
    t.mass_source = fmt::format(
        "estimated from its body ({:.0f} LDU³ at the mean density of the paper's bricks)",
        t.shape.body_volume());
  }
  // A part that takes studs in cells of its own is analysed through them, whatever else it does:
  // a hinge half or a turntable base is held by its studs, and what hangs on its hinge or turns
  // on it is carried where its own studs meet nothing that stands (report/audit.cpp). Minifigure
  // parts are carried whatever their cells (PHYSICS.md): a head's cell takes a neck.
  const bool turns_on_knuckles = std::any_of(t.shape.shafts.begin(), t.shape.shafts.end(),
                                             [](const Shaft& s) { return s.knuckle(); });
  if (!k.carried &&
      (minifigure(g) || (t.shape.receptacles.empty() && !turns_on_knuckles && !t.rolls)))
    k.carried = carried_by_name(g);
  if (!k.carried && t.shape.studs.empty() && t.shape.receptacles.empty() && t.shape.shafts.empty())
    k.carried = PartRole::NoConnections;
  return k;
}

}  // namespace lego::parts
