#include "physics/table.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/clp_lp.h"
#include "physics/connectivity.h"
#include "physics/contact_graph.h"
#include "physics/world_shape.h"

namespace lego::physics {
namespace {

using Point = std::array<double, 2>;  // (x, z)

double cross(const Point& o, const Point& a, const Point& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Whether `p` lies within `tolerance` of the convex hull of `points` (Andrew's monotone chain).
bool over_hull(std::vector<Point> points, const Point& p, double tolerance) {
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.empty()) return false;
  std::vector<Point> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  // Inside, or within `tolerance` of an edge (a hull of one or two points is all edge).
  bool inside = hull.size() >= 3;
  for (size_t i = 0; i < hull.size(); ++i) {
    const Point& a = hull[i];
    const Point& b = hull[(i + 1) % hull.size()];
    const double dx = b[0] - a[0], dz = b[1] - a[1], length2 = dx * dx + dz * dz;
    const double t = length2 > 0
                         ? std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dz) / length2, 0.0, 1.0)
                         : 0.0;
    if (std::hypot(a[0] + t * dx - p[0], a[1] + t * dz - p[1]) <= tolerance) return true;
    if (cross(a, b, p) < 0) inside = false;
  }
  return inside;
}

}  // namespace

Table rest_on_table(const std::vector<Vec3>& points, const Vec3& centre, double settle) {
  Table level;
  if (points.empty()) return level;
  double lowest = std::numeric_limits<double>::infinity();
  for (const Vec3& p : points) lowest = std::min(lowest, p[1]);
  level.height = lowest;
  std::vector<Point> touching;
  for (const Vec3& p : points)
    if (p[1] <= lowest + settle) touching.push_back({p[0], p[2]});
  if (over_hull(touching, {centre[0], centre[2]}, 0.5)) return level;
  // max c over (s_x, s_z, c): c + s_x (x - x_c) + s_z (z - z_c) <= y at every point, the plane
  // measured from the centre of mass.
  LpData lp;
  lp.rows = int(points.size());
  std::vector<std::pair<int, double>> along_x, along_z, up;
  for (int i = 0; i < lp.rows; ++i) {
    along_x.emplace_back(i, points[size_t(i)][0] - centre[0]);
    along_z.emplace_back(i, points[size_t(i)][2] - centre[2]);
    up.emplace_back(i, 1.0);
    lp.row_lower.push_back(-std::numeric_limits<double>::infinity());
    lp.row_upper.push_back(points[size_t(i)][1]);
  }
  lp.add_column(-kMaxTableSlope, kMaxTableSlope, 0, along_x);
  lp.add_column(-kMaxTableSlope, kMaxTableSlope, 0, along_z);
  lp.add_column(-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                -1, up);
  const LpSolution s = solve_lp(lp, LpMethod::DualSimplex, true, true, 10);
  const double sx = s.x.empty() ? 0 : s.x[0], sz = s.x.empty() ? 0 : s.x[1];
  // Against the limit, the model tips over on any table: the level one shows it falling.
  if (s.outcome != LpOutcome::Optimal ||
      std::max(std::abs(sx), std::abs(sz)) >= kMaxTableSlope * (1 - 1e-9)) {
    level.tips = true;
    return level;
  }
  Table tilted;
  tilted.slope = {sx, sz};
  tilted.height = s.x[2] - sx * centre[0] - sz * centre[2];
  return tilted;
}

Table settle_on_table(const Assembly& a, const ContactGraph& g, const Connectivity& c) {
  std::vector<Vec3> points;
  Vec3 weighted{0, 0, 0};
  double mass = 0;
  auto weigh = [&](const Vec3& centre, double m) {
    for (size_t k = 0; k < 3; ++k) weighted[k] += m * centre[k];
    mass += m;
  };
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    const bool fixed = !g.fixed.empty() && g.fixed[i];
    if (!fixed && (c.component[i] < 0 || !c.grounded[size_t(c.component[i])])) continue;
    const Brick& brick = a.bricks[i];
    weigh(body_centre(brick), brick.mass_g());
    if (brick.frame && tilted(*brick.frame)) continue;  // it stands on no table
    for (const Box& b : world_shape(brick).body) {
      const Box mb = model_bounds(brick, b);
      for (double x : {mb.min[0], mb.max[0]})
        for (double z : {mb.min[2], mb.max[2]}) points.push_back({x, mb.min[1], z});
    }
  }
  std::vector<char> floats(a.carried.size(), 0);
  for (int k : c.floating_carried) floats[size_t(k)] = 1;
  for (size_t k = 0; k < a.carried.size(); ++k) {
    if (floats[k]) continue;
    Vec3 centre{0, 0, 0};
    double volume = 0;
    for (const OrientedBox& o : world_boxes(a.carried[k])) {
      const double v = std::max(8 * o.half[0] * o.half[1] * o.half[2], 1e-9);
      for (size_t x = 0; x < 3; ++x) centre[x] += v * o.centre[x];
      volume += v;
    }
    if (volume > 0) {
      for (double& x : centre) x /= volume;
      weigh(centre, a.carried[k].mass_g);
    }
    for (const Vec3& p : world_outline(a.carried[k])) points.push_back(p);
  }
  if (points.empty() || mass <= 0) return Table{g.ground_height, {0, 0}};
  double lowest = points.front()[1];
  for (const Vec3& p : points) lowest = std::min(lowest, p[1]);
  std::erase_if(points, [&](const Vec3& p) { return p[1] > lowest + kLduPerPlate; });
  for (double& x : weighted) x /= mass;
  return rest_on_table(points, weighted, kSettleLdu);
}

}  // namespace lego::physics
