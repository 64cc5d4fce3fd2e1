#include "layout/pieces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>

#include "layout/components.h"

namespace lego::layout {
namespace {

// The 26 neighbours of a cell.
std::vector<std::array<int, 3>> neighbours26() {
  std::vector<std::array<int, 3>> out;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dz = -1; dz <= 1; ++dz)
      for (int dx = -1; dx <= 1; ++dx)
        if (dx || dy || dz) out.push_back({dx, dy, dz});
  return out;
}

struct Cell3 {
  int x, y, z;
};

Cell3 cell_of(const Target& t, size_t i) {
  return {int(i % size_t(t.width)), int(i / (size_t(t.width) * t.depth)),
          int((i / size_t(t.width)) % size_t(t.depth))};
}

// Voxels over a gap between a and b (26-neighbours in different parts) in `layer`: the empty
// cells of the rectangle spanning both. They take the colour of a filled cell there, else of a
// side, so that one brick may cover the rectangle.
std::vector<std::pair<Cell3, int>> bridge(const Target& t, Cell3 a, Cell3 b, int layer) {
  if (layer < 0 || layer >= t.height) return {};
  const int x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x);
  const int z0 = std::min(a.z, b.z), z1 = std::max(a.z, b.z);
  int color = kEmpty;
  for (int z = z0; z <= z1 && color == kEmpty; ++z)
    for (int x = x0; x <= x1 && color == kEmpty; ++x) color = t.at(x, layer, z);
  if (color == kEmpty)
    color = t.at(a.x, a.y, a.z) != kIgnore ? t.at(a.x, a.y, a.z) : t.at(b.x, b.y, b.z);
  std::vector<std::pair<Cell3, int>> cells;
  for (int z = z0; z <= z1; ++z)
    for (int x = x0; x <= x1; ++x)
      if (t.at(x, layer, z) == kEmpty) cells.push_back({{x, layer, z}, color});
  return cells;
}

// The layers a bridge between a and b may take: above and below them when they share a layer,
// else either of their two layers (over the lower one, or under the upper one).
std::array<int, 2> bridge_layers(Cell3 a, Cell3 b) {
  if (a.y == b.y) return {a.y + 1, a.y - 1};
  return {std::max(a.y, b.y), std::min(a.y, b.y)};
}

// The target's objects: its 26-connected parts, numbered in scan order.
struct Objects {
  struct Object {
    int lowest = 0;
    size_t first = 0, voxels = 0;
  };
  std::vector<int> label;  // per voxel, its object; -1 where empty
  std::vector<Object> list;

  // The objects lowest first, then in scan order.
  std::vector<size_t> by_lowest() const {
    std::vector<size_t> order(list.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t p, size_t q) { return list[p].lowest < list[q].lowest; });
    return order;
  }
};

Objects label_objects(const Target& t) {
  const auto steps = neighbours26();
  Objects out;
  out.label.assign(t.color.size(), -1);
  std::deque<size_t> queue;
  for (size_t start = 0; start < t.color.size(); ++start) {
    if (t.color[start] == kEmpty || out.label[start] >= 0) continue;
    const int id = int(out.list.size());
    out.list.push_back({cell_of(t, start).y, start, 0});
    out.label[start] = id;
    queue.push_back(start);
    while (!queue.empty()) {
      const size_t i = queue.front();
      queue.pop_front();
      const Cell3 c = cell_of(t, i);
      out.list[size_t(id)].lowest = std::min(out.list[size_t(id)].lowest, c.y);
      ++out.list[size_t(id)].voxels;
      for (const auto& s : steps) {
        const int x = c.x + s[0], y = c.y + s[1], z = c.z + s[2];
        if (t.at(x, y, z) == kEmpty) continue;
        const size_t n = t.index(x, y, z);
        if (out.label[n] >= 0) continue;
        out.label[n] = id;
        queue.push_back(n);
      }
    }
  }
  return out;
}

}  // namespace

std::vector<Piece> split_pieces(const Target& t) {
  const Objects labelled = label_objects(t);
  const std::vector<int>& label = labelled.label;
  const auto& objects = labelled.list;
  // Piece per object: the grounded ones share piece 0.
  std::vector<int> piece_of(objects.size(), -1);
  std::vector<Piece> pieces;
  bool any_grounded = false;
  for (const auto& o : objects) any_grounded = any_grounded || o.lowest == 0;
  if (any_grounded) pieces.push_back({Target(t.width, t.height, t.depth), 0, 0, 0});
  for (size_t k : labelled.by_lowest()) {
    const auto& o = objects[k];
    if (o.lowest == 0) {
      piece_of[k] = 0;
    } else {
      piece_of[k] = int(pieces.size());
      pieces.push_back({Target(t.width, t.height - o.lowest, t.depth), o.lowest, 0, 0});
    }
    Piece& p = pieces[size_t(piece_of[k])];
    ++p.objects;
    p.voxels += o.voxels;
  }
  for (size_t i = 0; i < t.color.size(); ++i) {
    if (label[i] < 0) continue;
    Piece& p = pieces[size_t(piece_of[size_t(label[i])])];
    const Cell3 c = cell_of(t, i);
    p.target.set(c.x, c.y - p.lift, c.z, t.color[i]);
  }
  return pieces;
}

FloatingSupports stand_floating_objects(Target& t, int max_columns) {
  FloatingSupports out;
  const Objects labelled = label_objects(t);
  std::vector<std::vector<size_t>> voxels_of(labelled.list.size());
  for (size_t i = 0; i < t.color.size(); ++i)
    if (labelled.label[i] >= 0) voxels_of[size_t(labelled.label[i])].push_back(i);
  const size_t plan = size_t(t.width) * size_t(t.depth);
  for (size_t id : labelled.by_lowest()) {
    if (labelled.list[id].lowest == 0) continue;
    // Per cell of the plan the object covers: its lowest voxel there; and its mass centre.
    std::vector<int> bottom(plan, -1);
    double cx = 0, cz = 0;
    for (size_t i : voxels_of[id]) {
      const Cell3 c = cell_of(t, i);
      int& b = bottom[size_t(c.z) * t.width + c.x];
      if (b < 0 || c.y < b) b = c.y;
      cx += c.x + 0.5;
      cz += c.z + 0.5;
    }
    cx /= double(voxels_of[id].size());
    cz /= double(voxels_of[id].size());
    auto covered = [&](int x, int z) {
      return x >= 0 && z >= 0 && x < t.width && z < t.depth && bottom[size_t(z) * t.width + x] >= 0;
    };
    // Columns two voxels square where the object is that wide (a 2 x 2 brick on a 2 x 2 brick
    // holds by four knobs), else one.
    int side = 1;
    for (size_t cell = 0; cell < plan && side == 1; ++cell) {
      const int x = int(cell % size_t(t.width)), z = int(cell / size_t(t.width));
      if (covered(x, z) && covered(x + 1, z) && covered(x, z + 1) && covered(x + 1, z + 1))
        side = 2;
    }
    struct Candidate {
      int x, z;
      double cx, cz;
    };
    std::vector<Candidate> candidates;
    for (int z = 0; z + side <= t.depth; ++z)
      for (int x = 0; x + side <= t.width; ++x) {
        bool all = true;
        for (int dz = 0; dz < side && all; ++dz)
          for (int dx = 0; dx < side && all; ++dx) all = covered(x + dx, z + dz);
        if (all) candidates.push_back({x, z, x + side / 2.0, z + side / 2.0});
      }
    // The column nearest the mass centre, then each the farthest from those chosen (the object's
    // ends), while they stand apart.
    auto distance = [](double ax, double az, double bx, double bz) {
      return std::hypot(ax - bx, az - bz);
    };
    std::vector<Candidate> chosen;
    const auto nearest = std::min_element(
        candidates.begin(), candidates.end(), [&](const Candidate& a, const Candidate& b) {
          return distance(a.cx, a.cz, cx, cz) < distance(b.cx, b.cz, cx, cz);
        });
    chosen.push_back(*nearest);
    while (int(chosen.size()) < max_columns) {
      double farthest = 0;
      const Candidate* next = nullptr;
      for (const Candidate& c : candidates) {
        double d = HUGE_VAL;
        for (const Candidate& k : chosen) d = std::min(d, distance(c.cx, c.cz, k.cx, k.cz));
        if (d > farthest) farthest = d, next = &c;
      }
      if (!next || farthest < kFloatingColumnSpacing) break;
      chosen.push_back(*next);
    }
    // Each column down from the object to what is under it, or the ground.
    for (const Candidate& c : chosen) {
      for (int dz = 0; dz < side; ++dz)
        for (int dx = 0; dx < side; ++dx) {
          const int x = c.x + dx, z = c.z + dz;
          for (int y = bottom[size_t(z) * t.width + x] - 1; y >= 0 && t.at(x, y, z) == kEmpty;
               --y) {
            t.set(x, y, z, kSupport);
            ++out.voxels;
          }
        }
      ++out.columns;
    }
    ++out.objects;
  }
  if (out.objects > 0)
    for (const auto& o : label_objects(t).list) out.still_floating += o.lowest > 0;
  return out;
}

JoinedLayout initialize_joined(Target target, const MergeRules& rules, Random& rng,
                               const ConnectOptions& options, int max_rounds) {
  const auto steps = neighbours26();
  JoinedLayout out;
  out.layout.emplace(std::move(target));
  Layout& layout = *out.layout;
  // The first layout keeps every colour exact; only where it breaks apart may colours be traded
  // (MergeRules::trades), around the bricks Algorithm 5 reconfigures.
  MergeRules exact = rules;
  exact.trades = {};
  out.connect = initialize_layout(layout, exact, rng, options);
  out.pieces_before = out.connect.components;
  if (!out.connect.single && !rules.trades.close.empty())
    out.connect = connect_components(layout, rules, rng, options);
  ++out.rounds;
  // Bridges go into this layout as 1x1 bricks, and Algorithm 5 goes on from it: the bridges are
  // where the parts meet, so it reconfigures there first, and what it joined stays joined.
  while (!out.connect.single && out.rounds <= max_rounds) {
    // Which part each brick is in; the part on the ground (or the largest) is the one the others
    // break off from. A random stream of its own, so that this leaves the layout's alone.
    Random own(uint64_t(out.rounds));
    const ComponentAnalysis parts = analyze_components(layout, own, options.ground_connects);
    auto part_at = [&](int x, int y, int z) {
      const int brick = layout.brick_at(x, y, z);
      return brick < 0 ? -1 : parts.component[size_t(brick)];
    };
    int main_part =
        int(std::max_element(parts.sizes.begin(), parts.sizes.end()) - parts.sizes.begin());
    for (int z = 0; z < layout.depth() && options.ground_connects; ++z)
      for (int x = 0; x < layout.width(); ++x)
        if (const int p = part_at(x, 0, z); p >= 0) main_part = p;
    // Per part, the smallest bridge to another part: fewest new voxels, and no new voxel left
    // with nothing above or below it (it would be a part of its own until a brick takes it).
    const Target& t = layout.target();
    auto cost = [&](const std::vector<std::pair<Cell3, int>>& cells) {
      size_t c = 0;
      for (const auto& [v, color] : cells)
        c += t.at(v.x, v.y - 1, v.z) == kEmpty && t.at(v.x, v.y + 1, v.z) == kEmpty ? 10 : 1;
      return c;
    };
    std::vector<std::vector<std::pair<Cell3, int>>> best(size_t(parts.count));
    std::vector<size_t> best_cost(size_t(parts.count), SIZE_MAX);
    best_cost[size_t(main_part)] = 0;  // the main part is bridged to, not from
    for (size_t i = 0; i < t.color.size(); ++i) {
      if (t.color[i] == kEmpty) continue;
      const Cell3 a = cell_of(t, i);
      const int pa = part_at(a.x, a.y, a.z);
      if (pa < 0 || best_cost[size_t(pa)] <= 1) continue;
      for (const auto& s : steps) {
        const Cell3 b{a.x + s[0], a.y + s[1], a.z + s[2]};
        const int pb = part_at(b.x, b.y, b.z);
        if (pb < 0 || pb == pa) continue;
        for (int layer : bridge_layers(a, b)) {
          auto cells = bridge(t, a, b, layer);
          if (cells.empty()) continue;
          if (const size_t c = cost(cells); c < best_cost[size_t(pa)]) {
            best_cost[size_t(pa)] = c;
            best[size_t(pa)] = std::move(cells);
          }
        }
      }
    }
    std::vector<std::pair<Cell3, int>> grow;
    for (const auto& cells : best) grow.insert(grow.end(), cells.begin(), cells.end());
    size_t added = 0;
    for (const auto& [c, color] : grow)
      if (layout.target().at(c.x, c.y, c.z) == kEmpty) {
        layout.grow(c.x, c.y, c.z, color);
        ++added;
      }
    if (added == 0) break;
    out.voxels_added += added;
    ++out.rounds;
    out.connect = connect_components(layout, rules, rng, options);
  }
  return out;
}

}  // namespace lego::layout
