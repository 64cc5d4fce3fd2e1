#include "voxel/voxelize.h"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>

#include "core/error.h"
#include "core/lattice.h"
#include "voxel/visibility.h"

namespace lego::voxel {
namespace {

using V = std::array<double, 3>;

V sub(const V& a, const V& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V& a, const V& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Triangle against the unit cube centred at c (half size 0.5): the 13 separating axes of
// Akenine-Möller's test (box normals, triangle normal, edge × box-axis products).
bool overlaps(const std::array<V, 3>& tri, const V& c) {
  const V v0 = sub(tri[0], c), v1 = sub(tri[1], c), v2 = sub(tri[2], c);
  const V e[3] = {sub(v1, v0), sub(v2, v1), sub(v0, v2)};
  const double h = 0.5;
  for (int a = 0; a < 3; ++a) {
    double lo = std::min({v0[a], v1[a], v2[a]}), hi = std::max({v0[a], v1[a], v2[a]});
    if (lo > h || hi < -h) return false;
  }
  for (const V& edge : e)
    for (int a = 0; a < 3; ++a) {
      V axis{0, 0, 0};
      axis[a] = 1;
      V n = cross(edge, axis);
      double p0 = dot(v0, n), p1 = dot(v1, n), p2 = dot(v2, n);
      double r = h * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  const V n = cross(e[0], e[1]);
  const double r = h * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
  return std::abs(dot(n, v0)) <= r;
}

// The grid's voxel size (a brick's height, a stud's width) from --height, --size or --scale, and
// its cells, all empty; a grid beyond the budget is refused.
void size_grid(const mesh::Mesh& m, const VoxelizeOptions& o, VoxelGrid& g) {
  const double ex = m.max.x - m.min.x, ey = m.max.y - m.min.y, ez = m.max.z - m.min.z;
  if (!(ey > 0) && !(ex > 0) && !(ez > 0)) throw InputError(m.source, 0, "the mesh has no extent");
  // A brick is 24 LDU high, a stud 20 LDU wide: a voxel is 1.2 times taller than wide.
  const double tall = double(kPlatesPerBrick * kLduPerPlate) / kLduPerStud;
  if (o.mm_per_unit > 0) {
    g.brick = kMmPerPlate * kPlatesPerBrick / o.mm_per_unit;
  } else if (o.fit[0] > 0 && o.fit[1] > 0 && o.fit[2] > 0) {
    g.brick = std::max({ey / o.fit[1], ex / o.fit[0] * tall, ez / o.fit[2] * tall});
  } else {
    if (o.height_bricks < 1) throw InputError(m.source, 0, "the height must be at least one brick");
    if (!(ey > 0))
      throw InputError(m.source, 0,
                       "the mesh is flat: it has no height to scale (use --size or --scale)");
    g.brick = ey / o.height_bricks;
  }
  g.stud = g.brick / tall;
  g.origin = m.min;
  // Counted in doubles and checked against the budget before they become ints: a mesh 3e9 units
  // wide must be refused, not wrap around into a small grid.
  auto cells = [](double extent, double size) {
    return std::max(1.0, std::ceil(extent / size - 1e-9));
  };
  const double width = cells(ex, g.stud), height = cells(ey, g.brick), depth = cells(ez, g.stud);
  const double total = width * height * depth;
  if (!(total <= double(o.max_voxels)))
    throw InputError(m.source, 0,
                     fmt::format("{:.0f} x {:.0f} x {:.0f} voxels is more than the budget of {} "
                                 "(--max-voxels)",
                                 width, height, depth, o.max_voxels));
  if (!(std::max({width, height, depth}) <= double(o.max_side)))
    throw InputError(m.source, 0,
                     fmt::format("{:.0f} x {:.0f} x {:.0f} voxels has a side longer than {} voxels "
                                 "(the mesh is that much longer than high): give its size with "
                                 "--size WxHxD or --scale",
                                 width, height, depth, o.max_side));
  g.width = int(width), g.height = int(height), g.depth = int(depth);
  g.cells.assign(size_t(total), Cell::Empty);
  g.color.assign(size_t(total), mesh::Rgb{0, 0, 0});
}

V to_grid(const VoxelGrid& g, const mesh::Vec3& p) {
  return {(p.x - g.origin.x) / g.stud, (p.y - g.origin.y) / g.brick, (p.z - g.origin.z) / g.stud};
}

// Every voxel a triangle overlaps is surface, coloured by the area-weighted mean of the mesh's
// colours in it.
void mark_surface(const mesh::Mesh& m, VoxelGrid& g) {
  std::vector<double> weight(g.cells.size(), 0.0);
  // The mean color of the first triangle touching a voxel, for voxels no sample point falls in.
  std::vector<mesh::Rgb> fallback(g.cells.size());

  for (const auto& t : m.triangles) {
    const std::array<V, 3> tri = {to_grid(g, t.v[0]), to_grid(g, t.v[1]), to_grid(g, t.v[2])};
    int lo[3], hi[3];
    const int size[3] = {g.width, g.height, g.depth};
    for (int a = 0; a < 3; ++a) {
      lo[a] =
          std::clamp(int(std::floor(std::min({tri[0][a], tri[1][a], tri[2][a]}))), 0, size[a] - 1);
      hi[a] =
          std::clamp(int(std::floor(std::max({tri[0][a], tri[1][a], tri[2][a]}))), 0, size[a] - 1);
    }
    const mesh::Rgb mean = m.color_at(t, 1.0 / 3, 1.0 / 3, 1.0 / 3);
    // Area-weighted color: sample the triangle on a grid finer than half a voxel.
    const double area_world = [&] {
      V a{t.v[1].x - t.v[0].x, t.v[1].y - t.v[0].y, t.v[1].z - t.v[0].z};
      V b{t.v[2].x - t.v[0].x, t.v[2].y - t.v[0].y, t.v[2].z - t.v[0].z};
      V n = cross(a, b);
      return 0.5 * std::sqrt(dot(n, n));
    }();
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      V d = sub(tri[(k + 1) % 3], tri[k]);
      longest = std::max(longest, std::sqrt(dot(d, d)));
    }
    const int n = std::clamp(int(std::ceil(2 * longest)), 1, 512);
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j)
        for (int up = 0; up < (i + j + 1 < n ? 2 : 1); ++up) {
          // Centroid of the sub-triangle (i, j) pointing up or down: n² equal-area pieces.
          const double b1 = (up ? i + 2.0 / 3 : i + 1.0 / 3) / n,
                       b2 = (up ? j + 2.0 / 3 : j + 1.0 / 3) / n;
          const double b0 = 1 - b1 - b2;
          V p;
          for (int a = 0; a < 3; ++a) p[a] = b0 * tri[0][a] + b1 * tri[1][a] + b2 * tri[2][a];
          const int x = std::clamp(int(p[0]), 0, g.width - 1),
                    y = std::clamp(int(p[1]), 0, g.height - 1),
                    z = std::clamp(int(p[2]), 0, g.depth - 1);
          const size_t id = g.index(x, y, z);
          const double w = area_world / (double(n) * n);
          const mesh::Rgb c = m.color_at(t, b0, b1, b2);
          g.color[id].r += float(w * c.r);
          g.color[id].g += float(w * c.g);
          g.color[id].b += float(w * c.b);
          weight[id] += w;
        }
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int x = lo[0]; x <= hi[0]; ++x)
          if (overlaps(tri, {x + 0.5, y + 0.5, z + 0.5})) {
            const size_t id = g.index(x, y, z);
            if (g.cells[id] != Cell::Surface) fallback[id] = mean;
            g.cells[id] = Cell::Surface;
          }
  }
  for (size_t id = 0; id < g.cells.size(); ++id) {
    if (g.cells[id] != Cell::Surface) {
      g.color[id] = {};
    } else if (weight[id] > 0) {
      g.color[id] = {float(g.color[id].r / weight[id]), float(g.color[id].g / weight[id]),
                     float(g.color[id].b / weight[id])};
    } else {
      g.color[id] = fallback[id];  // a sliver of surface that no sample point fell into
    }
  }
}

// Inside: ray parity along each axis through voxel centres, then a majority of the three.
void mark_inside(const mesh::Mesh& m, VoxelGrid& g) {
  std::vector<uint8_t> votes(g.cells.size(), 0);
  const int size[3] = {g.width, g.height, g.depth};
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    std::vector<std::vector<double>> hits(static_cast<size_t>(size[b]) * size[c]);
    for (const auto& t : m.triangles) {
      const std::array<V, 3> tri = {to_grid(g, t.v[0]), to_grid(g, t.v[1]), to_grid(g, t.v[2])};
      const double area = (tri[1][b] - tri[0][b]) * (tri[2][c] - tri[0][c]) -
                          (tri[2][b] - tri[0][b]) * (tri[1][c] - tri[0][c]);
      if (std::abs(area) < 1e-12) continue;  // edge-on to this axis
      const int b0 = std::max(0, int(std::ceil(std::min({tri[0][b], tri[1][b], tri[2][b]}) - 0.5)));
      const int b1 =
          std::min(size[b] - 1, int(std::floor(std::max({tri[0][b], tri[1][b], tri[2][b]}) - 0.5)));
      const int c0 = std::max(0, int(std::ceil(std::min({tri[0][c], tri[1][c], tri[2][c]}) - 0.5)));
      const int c1 =
          std::min(size[c] - 1, int(std::floor(std::max({tri[0][c], tri[1][c], tri[2][c]}) - 0.5)));
      for (int i = b0; i <= b1; ++i)
        for (int j = c0; j <= c1; ++j) {
          const double pb = i + 0.5, pc = j + 0.5;
          double w[3];
          bool inside = true;
          for (int k = 0; k < 3 && inside; ++k) {
            const V& p = tri[(k + 1) % 3];
            const V& q = tri[(k + 2) % 3];
            w[k] = ((q[b] - p[b]) * (pc - p[c]) - (q[c] - p[c]) * (pb - p[b])) / area;
            // Half-open rule so a ray through a shared edge counts the crossing once.
            inside = w[k] > 0 ||
                     (w[k] == 0 && (q[c] > p[c] || (q[c] == p[c] && q[b] < p[b])) == (area > 0));
          }
          if (!inside) continue;
          hits[size_t(i) * size[c] + j].push_back(w[0] * tri[0][a] + w[1] * tri[1][a] +
                                                  w[2] * tri[2][a]);
        }
    }
    for (int i = 0; i < size[b]; ++i)
      for (int j = 0; j < size[c]; ++j) {
        auto& h = hits[size_t(i) * size[c] + j];
        std::sort(h.begin(), h.end());
        size_t next = 0;
        bool in = false;
        for (int k = 0; k < size[a]; ++k) {
          while (next < h.size() && h[next] < k + 0.5) in = !in, ++next;
          if (!in) continue;
          int p[3];
          p[a] = k, p[b] = i, p[c] = j;
          ++votes[g.index(p[0], p[1], p[2])];
        }
      }
  }
  for (size_t id = 0; id < g.cells.size(); ++id)
    if (g.cells[id] == Cell::Empty && votes[id] >= 2) g.cells[id] = Cell::Inside;
}

}  // namespace

size_t VoxelGrid::count(Cell c) const {
  return size_t(std::count(cells.begin(), cells.end(), c));
}

VoxelGrid voxelize(const mesh::Mesh& m, const VoxelizeOptions& o) {
  VoxelGrid g;
  size_grid(m, o, g);
  mark_surface(m, g);
  mark_inside(m, g);
  return g;
}

void hollow(VoxelGrid& g, int shell) {
  if (shell <= 0) return;
  std::vector<int> depth(g.cells.size(), -1);
  std::deque<std::array<int, 3>> queue;
  for (int y = 0; y < g.height; ++y)
    for (int z = 0; z < g.depth; ++z)
      for (int x = 0; x < g.width; ++x)
        if (g.at(x, y, z) == Cell::Surface) {
          depth[g.index(x, y, z)] = 0;
          queue.push_back({x, y, z});
        }
  while (!queue.empty()) {
    auto [x, y, z] = queue.front();
    queue.pop_front();
    const int d = depth[g.index(x, y, z)];
    for (const auto& s : kFaceSteps) {
      const int nx = x + s[0], ny = y + s[1], nz = z + s[2];
      if (g.at(nx, ny, nz) != Cell::Inside || depth[g.index(nx, ny, nz)] >= 0) continue;
      depth[g.index(nx, ny, nz)] = d + 1;
      queue.push_back({nx, ny, nz});
    }
  }
  for (size_t id = 0; id < g.cells.size(); ++id)
    if (g.cells[id] == Cell::Inside && (depth[id] < 0 || depth[id] >= shell))
      g.cells[id] = Cell::Empty;
}

size_t colour_seen_inside(VoxelGrid& g) {
  const auto filled = [&](size_t i) { return g.cells[i] != Cell::Empty; };
  std::vector<size_t> seen;
  for (size_t i : seen_from_outside(g.width, g.height, g.depth, filled))
    if (g.cells[i] == Cell::Inside) seen.push_back(i);
  if (seen.empty()) return 0;
  // The nearest Surface voxel through filled voxels: a breadth-first search from all of them.
  std::vector<int> source(g.cells.size(), -1);
  std::deque<size_t> queue;
  for (size_t i = 0; i < g.cells.size(); ++i)
    if (g.cells[i] == Cell::Surface) {
      source[i] = int(i);
      queue.push_back(i);
    }
  while (!queue.empty()) {
    const size_t i = queue.front();
    queue.pop_front();
    const int x = int(i % size_t(g.width)), z = int((i / size_t(g.width)) % size_t(g.depth)),
              y = int(i / (size_t(g.width) * g.depth));
    for (const auto& s : kFaceSteps) {
      const int nx = x + s[0], ny = y + s[1], nz = z + s[2];
      if (g.at(nx, ny, nz) != Cell::Inside) continue;
      const size_t n = g.index(nx, ny, nz);
      if (source[n] >= 0) continue;
      source[n] = source[i];
      queue.push_back(n);
    }
  }
  size_t coloured = 0;
  for (size_t i : seen) {
    if (source[i] < 0) continue;  // an inside without any surface: cannot happen, kept safe
    g.cells[i] = Cell::Surface;
    g.color[i] = g.color[size_t(source[i])];
    ++coloured;
  }
  return coloured;
}

}  // namespace lego::voxel
