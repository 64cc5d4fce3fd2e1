#include "layout/supports.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include "core/stopwatch.h"
#include "layout/refine.h"
#include "voxel/visibility.h"

namespace lego::layout {
namespace {

// A layer's height in studs (a brick is 24 LDU tall, a stud 20 LDU wide): how the columns' distance
// to a weak place counts layers.
constexpr double kLayerInStuds = double(kPlatesPerBrick * kLduPerPlate) / kLduPerStud;

// Per column (x, z) of the grid: the lowest layer with a voxel (the model's or a support's), or
// -1 when there is none.
std::vector<int> bottoms(const Target& t) {
  std::vector<int> out(size_t(t.width) * t.depth, -1);
  for (int z = 0; z < t.depth; ++z)
    for (int x = 0; x < t.width; ++x)
      for (int y = 0; y < t.height; ++y)
        if (t.at(x, y, z) != kEmpty) {
          out[size_t(z) * t.width + x] = y;
          break;
        }
  return out;
}

// Every column that fits: its footprint's cells empty from the ground up to the model, which
// hangs over at least one of them (a support already there fills its cells from the ground).
std::vector<SupportColumn> possible_columns(const Layout& layout) {
  const Target& t = layout.target();
  const std::vector<int> bottom = bottoms(t);
  auto bottom_at = [&](int x, int z) { return bottom[size_t(z) * t.width + x]; };
  std::vector<SupportColumn> out;
  for (const auto& [sx, sz] : {std::pair{2, 2}, std::pair{2, 1}, std::pair{1, 2}, std::pair{1, 1}})
    for (int z = 0; z + sz <= t.depth; ++z)
      for (int x = 0; x + sx <= t.width; ++x) {
        int top = -1;  // the lowest model voxel over the footprint
        bool ground_free = true;
        for (int dz = 0; dz < sz; ++dz)
          for (int dx = 0; dx < sx; ++dx) {
            const int b = bottom_at(x + dx, z + dz);
            if (b == 0) ground_free = false;
            if (b > 0) top = top < 0 ? b : std::min(top, b);
          }
        SupportColumn c{x, z, sx, sz, 0, top, false};
        if (ground_free && top > 0) out.push_back(c);
      }
  return out;
}

// The model's hollow: per cell, whether it is empty and enclosed by the model (not open to the
// outside through empty cells, voxel/visibility.h; Target's cells are indexed as its grid's).
std::vector<char> hollow_cells(const Target& t) {
  const std::vector<uint8_t> open = voxel::open_to_outside(
      t.width, t.height, t.depth, [&](size_t i) { return t.color[i] != kEmpty; });
  std::vector<char> hollow(t.color.size(), 0);
  for (size_t i = 0; i < hollow.size(); ++i) hollow[i] = t.color[i] == kEmpty && !open[i];
  return hollow;
}

// Every column that fits inside the model: a footprint's cells hollow over a run of layers, the
// run as long as it goes. The hollow is enclosed, so that the model is under the run (its floor)
// and over it (its ceiling) on some of the footprint's cells.
std::vector<SupportColumn> possible_inside_columns(const Layout& layout) {
  const Target& t = layout.target();
  const std::vector<char> hollow = hollow_cells(t);
  std::vector<SupportColumn> out;
  for (const auto& [sx, sz] : {std::pair{2, 2}, std::pair{2, 1}, std::pair{1, 2}, std::pair{1, 1}})
    for (int z = 0; z + sz <= t.depth; ++z)
      for (int x = 0; x + sx <= t.width; ++x) {
        auto all_hollow = [&](int y) {
          for (int dz = 0; dz < sz; ++dz)
            for (int dx = 0; dx < sx; ++dx)
              if (!hollow[t.index(x + dx, y, z + dz)]) return false;
          return true;
        };
        for (int y = 0; y < t.height;) {
          if (!all_hollow(y)) {
            ++y;
            continue;
          }
          const int bottom = y;
          while (y < t.height && all_hollow(y)) ++y;
          out.push_back({x, z, sx, sz, bottom, y - bottom, true});
        }
      }
  return out;
}

// The layout bricks the analysis names as where the model fails: those no forces balance, else
// the upper ends of its weakest contacts, weakest first, each once.
std::vector<int> weak_places(const physics::StabilityResult& r, const LayoutAssembly& la) {
  std::vector<int> bricks;
  if (r.status == physics::StabilityStatus::NoEquilibrium)
    bricks = r.unbalanced;
  else if (r.status == physics::StabilityStatus::Solved)
    for (const physics::WeakContact& w : r.weakest) bricks.push_back(w.upper);
  std::vector<int> out;
  for (int b : bricks)
    if (b >= 0 && size_t(b) < la.layout_id.size() &&
        std::find(out.begin(), out.end(), la.layout_id[size_t(b)]) == out.end())
      out.push_back(la.layout_id[size_t(b)]);
  return out;
}

// The columns tried for one weak place: those whose tops are nearest to it (the load it fails
// under comes through it; a layer is 1.2 studs tall), and those nearest below the centre of the
// mass at its layer and above (what hangs on it, when it is the root of an overhang), `each` of
// both, larger footprints first among equally near ones.
std::vector<SupportColumn> columns_to_try(const Layout& layout,
                                          const std::vector<SupportColumn>& possible,
                                          const LayoutBrick& weak, int each) {
  double mx = 0, mz = 0, mass = 0;
  for (int id : layout.brick_ids()) {
    const LayoutBrick& b = layout.brick(id);
    if (b.y < weak.y || b.color == kSupport) continue;
    mx += (b.x + b.size_x / 2.0) * b.voxels();
    mz += (b.z + b.size_z / 2.0) * b.voxels();
    mass += b.voxels();
  }
  struct Centre {
    double x, z;
    std::optional<int> layer;  // the height that counts, if any
  };
  std::vector<Centre> centres = {{weak.x + weak.size_x / 2.0, weak.z + weak.size_z / 2.0, weak.y}};
  if (mass > 0) centres.push_back({mx / mass, mz / mass, std::nullopt});
  std::vector<SupportColumn> out;
  for (const Centre& centre : centres) {
    auto distance = [&](const SupportColumn& c) {
      const double up = centre.layer ? kLayerInStuds * (c.top() - *centre.layer) : 0.0;
      return std::hypot(c.x + c.size_x / 2.0 - centre.x, c.z + c.size_z / 2.0 - centre.z, up);
    };
    std::vector<SupportColumn> nearest = possible;
    std::stable_sort(nearest.begin(), nearest.end(),
                     [&](const SupportColumn& a, const SupportColumn& b) {
                       const double da = distance(a), db = distance(b);
                       if (std::abs(da - db) > 0.5) return da < db;
                       return a.size_x * a.size_z > b.size_x * b.size_z;
                     });
    int taken = 0;
    for (const SupportColumn& c : nearest) {
      if (taken == each) break;
      const bool seen = std::any_of(out.begin(), out.end(), [&](const SupportColumn& d) {
        return d.x == c.x && d.z == c.z && d.size_x == c.size_x && d.size_z == c.size_z;
      });
      if (seen) continue;
      out.push_back(c);
      ++taken;
    }
  }
  return out;
}

// The inside columns whose tops are near the weak place (a layer counts 1.2 studs): the hollow
// far from it holds nothing up there, and each column tried costs an analysis.
constexpr double kInsideReach = 4;
std::vector<SupportColumn> within_reach(const std::vector<SupportColumn>& inside,
                                        const LayoutBrick& weak) {
  std::vector<SupportColumn> out;
  for (const SupportColumn& c : inside) {
    const double dx = std::max({0, weak.x - (c.x + c.size_x), c.x - (weak.x + weak.size_x)});
    const double dz = std::max({0, weak.z - (c.z + c.size_z), c.z - (weak.z + weak.size_z)});
    if (std::hypot(dx, dz, kLayerInStuds * (c.top() - weak.y)) <= kInsideReach) out.push_back(c);
  }
  return out;
}

// The column's bricks, one per layer; false when the limits (`--limit`, an inventory) do not allow
// them all.
bool build_column(Layout& layout, const SupportColumn& c, const Limits* limits) {
  for (int y = c.bottom; y < c.top(); ++y) {
    const LayoutBrick b{.x = c.x,
                        .y = y,
                        .z = c.z,
                        .size_x = c.size_x,
                        .size_z = c.size_z,
                        .color = c.inside ? kIgnore : kSupport};
    if (limits && !limits->allow(layout, b)) return false;
    layout.grow(b);
  }
  return true;
}

}  // namespace

Layout placed_only(const Layout& layout, const PlacedBricks& step) {
  Layout out = layout;
  for (int id : layout.brick_ids())
    if (layout.brick(id).color != kSupport &&
        (size_t(id) >= step.placed.size() || !step.placed[size_t(id)]))
      out.remove(id);
  return out;
}

namespace {

// The model judged: all of it with its loads, or a build step's bricks without them.
LayoutAssembly judged(const Layout& layout, const BrickCatalog& catalog, const SupportOptions& o,
                      const PlacedBricks& step) {
  return step.placed.empty()
             ? to_assembly(layout, catalog, o.inside_color, o.loads, o.support_color)
             : to_assembly(placed_only(layout, step), catalog, o.inside_color, {}, o.support_color);
}

// A column built on a copy of the layout, and the analysis of what is judged with it.
struct Trial {
  Layout layout;
  LayoutAssembly la;
  physics::StabilityResult result;
};

// Each of `tried` on a copy of the layout, two at a time with o.side_by_side; none where a column
// is beyond the limits.
std::vector<std::optional<Trial>> try_columns(const Layout& layout,
                                              const std::vector<SupportColumn>& tried,
                                              const BrickCatalog& catalog, const SupportOptions& o,
                                              const PlacedBricks& step) {
  std::vector<std::optional<Trial>> trials(tried.size());
  auto run = [&](size_t k) {
    Trial t{layout, {}, {}};
    if (!build_column(t.layout, tried[k], o.limits)) return;
    t.la = judged(t.layout, catalog, o, step);
    t.result = physics::analyze_stability(t.la.assembly, o.stability);
    trials[k] = std::move(t);
  };
  for (size_t k = 0; k < tried.size(); k += o.side_by_side ? 2 : 1) {
    if (o.side_by_side && k + 1 < tried.size()) {
      std::thread second(run, k + 1);
      run(k);
      second.join();
    } else {
      run(k);
    }
  }
  return trials;
}

// The best column against C_M `cm`: the largest C_M, or as good with the weak place `place` no
// longer the weakest. The first of equals, so that the result does not depend on threads.
std::optional<size_t> best_column(const std::vector<std::optional<Trial>>& trials, double cm,
                                  int place) {
  std::optional<size_t> best;
  double best_cm = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < trials.size(); ++k) {
    if (!trials[k]) continue;  // beyond the limits
    const double now = comparable_cm_gf(trials[k]->result);
    const std::vector<int> still = weak_places(trials[k]->result, trials[k]->la);
    const bool moved =
        std::isfinite(now) && now >= cm - 1e-9 && (still.empty() || still.front() != place);
    if ((now > cm + 1e-9 || moved) && (!best || now > best_cm + 1e-9)) {
      best = k;
      best_cm = now;
    }
  }
  return best;
}

// add_supports from the judged model `la` as it is and its analysis `current`.
SupportResult add_columns(Layout& layout, const BrickCatalog& catalog, LayoutAssembly la,
                          const physics::StabilityResult& current, const SupportOptions& o,
                          const PlacedBricks& step) {
  const auto start = std::chrono::steady_clock::now();
  SupportResult out;
  out.final = current;
  out.stable = out.final.stable(o.min_cm_gf);
  // As it was after the last column that raised C_M. Columns that only move the weakest place
  // elsewhere are kept while a next one may raise it (two legs as weak as each other), at most
  // kMoves in a row, and taken back when none does.
  constexpr int kMoves = 3;
  constexpr double kGainGf = 0.01;  // less is not worth a column
  struct Gain {
    Layout layout;
    LayoutAssembly la;
    physics::StabilityResult result;
    size_t columns = 0, voxels = 0, inside_voxels = 0;
  };
  std::optional<Gain> gain;
  int moves = 0;
  constexpr int kWider = 3;  // columns tried per place when the nearest did not help
  bool widened = false;
  auto take_back_moves = [&] {
    if (moves == 0 || !gain) return;
    layout = std::move(gain->layout);
    la = std::move(gain->la);
    out.final = std::move(gain->result);
    out.columns.resize(gain->columns);
    out.voxels = gain->voxels;
    out.inside_voxels = gain->inside_voxels;
    out.stable = out.final.stable(o.min_cm_gf);
  };
  if (!out.stable) gain = Gain{layout, la, out.final, 0, 0, 0};
  std::vector<int> hollow_tried;  // weak places (layout ids) whose hollow columns were tried
  while (!out.stable && int(out.columns.size()) < o.max_columns && moves <= kMoves) {
    const double cm = comparable_cm_gf(out.final);
    const std::vector<int> places = weak_places(out.final, la);
    const std::vector<SupportColumn> possible = possible_columns(layout);
    // The hollow's columns only for the finished model: under a build step, a column inside is
    // built with its layers, not before the step.
    const std::vector<SupportColumn> inside =
        step.placed.empty() ? possible_inside_columns(layout) : std::vector<SupportColumn>{};
    bool kept = false;
    const int tries = widened ? o.tries_per_place * kWider : o.tries_per_place;
    for (size_t p = 0; p < places.size() && int(p) < o.weak_places_per_round && !kept; ++p) {
      if (seconds_since(start) > o.max_seconds) {
        out.out_of_time = true;
        take_back_moves();
        return out;
      }
      const LayoutBrick& weak = layout.brick(places[p]);
      // The hollow near the weak place first (once per place: columns added elsewhere seldom
      // make one there help, and each costs an analysis); the ground's where none of it helps.
      std::vector<SupportColumn> tried;
      if (std::find(hollow_tried.begin(), hollow_tried.end(), places[p]) == hollow_tried.end()) {
        tried = columns_to_try(layout, within_reach(inside, weak), weak, tries);
        hollow_tried.push_back(places[p]);
      }
      std::vector<std::optional<Trial>> trials = try_columns(layout, tried, catalog, o, step);
      out.analyses += int(tried.size());
      std::optional<size_t> best = best_column(trials, cm, places[p]);
      if (!best) {
        tried = columns_to_try(layout, possible, weak, tries);
        trials = try_columns(layout, tried, catalog, o, step);
        out.analyses += int(tried.size());
        best = best_column(trials, cm, places[p]);
      }
      if (!best) continue;
      const double best_cm = comparable_cm_gf(trials[*best]->result);
      Trial& t = *trials[*best];
      layout = std::move(t.layout);
      la = std::move(t.la);
      out.final = std::move(t.result);
      const SupportColumn& c = tried[*best];
      out.columns.push_back(c);
      (c.inside ? out.inside_voxels : out.voxels) += size_t(c.layers * c.size_x * c.size_z);
      out.stable = out.final.stable(o.min_cm_gf);
      kept = true;
      if (best_cm > cm + kGainGf) {
        moves = 0;
        gain = Gain{layout, la, out.final, out.columns.size(), out.voxels, out.inside_voxels};
      } else {
        ++moves;
      }
      if (o.progress) o.progress(int(out.columns.size()), comparable_cm_gf(out.final));
    }
    // Where the nearest columns do not help, once more with more of them before giving up.
    if (!kept && widened) break;
    widened = !kept;
  }
  take_back_moves();
  return out;
}

}  // namespace

int SupportResult::inside_columns() const {
  return int(std::count_if(columns.begin(), columns.end(),
                           [](const SupportColumn& c) { return c.inside; }));
}

SupportResult add_supports(Layout& layout, const BrickCatalog& catalog,
                           const physics::StabilityResult& current, const SupportOptions& o) {
  return add_columns(layout, catalog, judged(layout, catalog, o, {}), current, o, {});
}

SupportResult add_supports(Layout& layout, const BrickCatalog& catalog, const SupportOptions& o,
                           const PlacedBricks& step) {
  LayoutAssembly la = judged(layout, catalog, o, step);
  const physics::StabilityResult current = physics::analyze_stability(la.assembly, o.stability);
  return add_columns(layout, catalog, std::move(la), current, o, step);
}

}  // namespace lego::layout
