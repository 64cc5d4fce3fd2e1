#include "layout/merge.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ldraw/color_table.h"
#include "voxel/palette.h"

namespace lego::layout {

const Family& standard_family() {
  static const Family family{{1, 1}, {2, 1}, {3, 1}, {4, 1}, {6, 1}, {8, 1},
                             {2, 2}, {3, 2}, {4, 2}, {6, 2}, {8, 2}};
  return family;
}

std::optional<LayoutBrick> merged_shape(const Layout& layout, int a, int b, const Family& family) {
  const LayoutBrick& p = layout.brick(a);
  const LayoutBrick& q = layout.brick(b);
  if (p.y != q.y) return std::nullopt;
  LayoutBrick m = p;
  if (p.z == q.z && p.size_z == q.size_z && (p.max_x() == q.x || q.max_x() == p.x)) {
    m.x = std::min(p.x, q.x);
    m.size_x = p.size_x + q.size_x;
  } else if (p.x == q.x && p.size_x == q.size_x && (p.max_z() == q.z || q.max_z() == p.z)) {
    m.z = std::min(p.z, q.z);
    m.size_z = p.size_z + q.size_z;
  } else {
    return std::nullopt;
  }
  if (std::find(family.begin(), family.end(), std::pair{m.length(), m.width()}) == family.end())
    return std::nullopt;
  m.color = p.color == kIgnore ? q.color : p.color;  // cases 1-3; case 4 keeps p's for now
  return m;
}

std::optional<LayoutBrick> merge_of(const Layout& layout, int a, int b, const MergeRules& rules) {
  auto m = merged_shape(layout, a, b, rules.family);
  if (!m) return std::nullopt;
  const int ca = layout.brick(a).color, cb = layout.brick(b).color;
  // A support comes away whole: no brick is half support, whatever the colour rule.
  if ((ca == kSupport) != (cb == kSupport)) return std::nullopt;
  const bool two_colors = ca != kIgnore && cb != kIgnore && ca != cb;
  if (!two_colors) return rules.limits.allow(layout, *m) ? m : std::nullopt;
  if (rules.color == ColorRule::Hard && !rules.trades.allowed(ca, cb)) return std::nullopt;
  LayoutBrick other = *m;
  other.color = cb;
  return rules.limits.allow(layout, *m) || rules.limits.allow(layout, other) ? m : std::nullopt;
}

bool mergeable(const Layout& layout, int a, int b, const MergeRules& rules) {
  return merge_of(layout, a, b, rules).has_value();
}

int color_mismatches(const Layout& layout, const LayoutBrick& brick) {
  int e = 0;
  for (int z = brick.z; z < brick.max_z(); ++z)
    for (int x = brick.x; x < brick.max_x(); ++x) {
      const int c = layout.target().at(x, brick.y, z);
      e += c != kIgnore && c != kEmpty && c != brick.color;
    }
  return e;
}

namespace {

// An LDraw colour in CIELAB, as the colour table gives it (black when the table lacks it).
voxel::Lab lab_of(int code) {
  const auto rgb = ldraw::ColorTable::standard().rgb(code);
  return voxel::to_lab(voxel::from_hex(rgb ? *rgb : 0));
}

}  // namespace

ColorChanges color_changes(const Layout& layout) {
  ColorChanges out;
  double sum = 0;
  for (int id : layout.brick_ids()) {
    const LayoutBrick& b = layout.brick(id);
    for (int z = b.z; z < b.max_z(); ++z)
      for (int x = b.x; x < b.max_x(); ++x) {
        const int c = layout.target().at(x, b.y, z);
        if (c < 0) continue;  // empty, IGNORE or a support: no colour of its own
        ++out.visible;
        if (c == b.color || b.color < 0) continue;
        ++out.changed;
        const double d = voxel::ciede2000(lab_of(c), lab_of(b.color));
        sum += d;
        out.max_distance = std::max(out.max_distance, d);
      }
  }
  if (out.changed > 0) out.mean_distance = sum / double(out.changed);
  return out;
}

namespace {

// Case 4 of the color assignment: choose c_i or c_j by importance sampling, or discard the merge.
// Returns false to discard.
bool choose_color(const Layout& layout, LayoutBrick& m, int ci, int cj, const MergeRules& rules,
                  Random& rng) {
  m.color = ci;
  const int ei = color_mismatches(layout, m);
  m.color = cj;
  const int ej = color_mismatches(layout, m);
  // A brick's color is always one of its voxels' colors, so e_i, e_j >= 1; guard anyway.
  const double wi = 1.0 / std::max(ei, 1), wj = 1.0 / std::max(ej, 1);
  const double u = rng.unit() * (wi + wj + rules.w_c);
  if (u < wi)
    m.color = ci;
  else if (u < wi + wj)
    m.color = cj;
  else
    return false;  // p_d
  return rules.limits.allow(layout, m);
}

// A colour trade under the hard rule: the colour of more of the brick's voxels (a's on a tie).
// Returns false when the limits do not allow it.
bool trade_color(const Layout& layout, LayoutBrick& m, int ci, int cj, const MergeRules& rules) {
  m.color = ci;
  const int ei = color_mismatches(layout, m);
  m.color = cj;
  const int ej = color_mismatches(layout, m);
  m.color = ej < ei ? cj : ci;
  return rules.limits.allow(layout, m);
}

}  // namespace

ColorTrades ColorTrades::within(const std::vector<int>& codes, double max_distance) {
  ColorTrades out;
  if (max_distance <= 0) return out;
  std::vector<std::pair<int, voxel::Lab>> labs;
  for (int code : codes)
    if (ldraw::ColorTable::standard().rgb(code)) labs.push_back({code, lab_of(code)});
  for (size_t i = 0; i < labs.size(); ++i)
    for (size_t k = i + 1; k < labs.size(); ++k)
      if (labs[i].first != labs[k].first &&
          voxel::ciede2000(labs[i].second, labs[k].second) <= max_distance)
        out.close.insert(
            {std::min(labs[i].first, labs[k].first), std::max(labs[i].first, labs[k].first)});
  return out;
}

namespace {

// The candidate pairs of Algorithm 4, bucketed by the area of the brick they would make, so a pop
// can favour small merges (see MergeRules::small_first) in O(buckets).
class PairPool {
 public:
  explicit PairPool(double small_first) {
    for (int area = 0; area < kBuckets; ++area)
      weight_[area] = area == 0 ? 0 : std::pow(double(area), -small_first);
  }
  void push(int a, int b, int area) { bucket_[area].emplace_back(a, b); }
  bool empty() const {
    return std::all_of(bucket_.begin(), bucket_.end(), [](auto& b) { return b.empty(); });
  }
  std::pair<int, int> pop(Random& rng) {
    double total = 0;
    for (int area = 0; area < kBuckets; ++area)
      total += weight_[area] * double(bucket_[area].size());
    double u = rng.unit() * total;
    int area = kBuckets - 1;
    for (int i = 0; i < kBuckets; ++i) {
      u -= weight_[i] * double(bucket_[i].size());
      if (u < 0 && !bucket_[i].empty()) {
        area = i;
        break;
      }
    }
    while (bucket_[area].empty()) --area;  // rounding at the very end of the range
    auto& pairs = bucket_[area];
    const size_t pick = rng.below(pairs.size());
    const auto pair = pairs[pick];
    pairs[pick] = pairs.back();
    pairs.pop_back();
    return pair;
  }

 private:
  static constexpr int kBuckets = 17;  // areas up to 2x8
  std::array<std::vector<std::pair<int, int>>, kBuckets> bucket_;
  std::array<double, kBuckets> weight_{};
};

}  // namespace

size_t random_merge(Layout& layout, std::span<const int> seeds, const MergeRules& rules,
                    Random& rng) {
  // Pairs whose brick died since they were listed are skipped when popped: that is the paper's
  // "remove any (b_i, .)", done lazily. Ids are not reused within an edit (removed bricks only
  // return to the free list when it commits), so a listed pair of living bricks is always the
  // pair it was; hence the edit opened here when the caller has none open.
  const bool own_edit = !layout.editing();
  if (own_edit) layout.begin_edit();
  PairPool pool(rules.small_first);
  auto offer = [&](int a, int b) {
    if (!mergeable(layout, a, b, rules)) return;
    const LayoutBrick &p = layout.brick(a), &q = layout.brick(b);
    pool.push(a, b, p.voxels() + q.voxels());
  };
  std::vector<char> seed(layout.id_limit(), 0);
  for (int s : seeds)
    if (layout.alive(s)) seed[s] = 1;
  std::vector<int> around;
  auto offer_all = [&](std::span<const int> bricks, bool skip_seed_duplicates) {
    for (int s : bricks) {
      if (!layout.alive(s)) continue;
      around.clear();
      layout.side_neighbours(s, around);
      for (int n : around)
        if (!skip_seed_duplicates || !seed[n] || s < n) offer(s, n);
    }
  };
  offer_all(seeds, true);
  size_t merges = 0;
  for (;;) {
    // A merge that removes a limited size frees room for merges discarded earlier, anywhere.
    bool freed_limited = false;
    while (!pool.empty()) {
      const auto [a, b] = pool.pop(rng);
      if (!layout.alive(a) || !layout.alive(b)) continue;
      // Counts may have changed since the pair was listed: check the rules again.
      std::optional<LayoutBrick> merged = merge_of(layout, a, b, rules);
      if (!merged) continue;
      LayoutBrick m = *merged;
      const int ca = layout.brick(a).color, cb = layout.brick(b).color;
      if (ca != kIgnore && cb != kIgnore && ca != cb &&
          !(rules.color == ColorRule::Hard ? trade_color(layout, m, ca, cb, rules)
                                           : choose_color(layout, m, ca, cb, rules, rng)))
        continue;
      for (int old : {a, b})
        freed_limited |=
            rules.limits.limits_size(layout.brick(old).length(), layout.brick(old).width());
      layout.remove(a);
      layout.remove(b);
      const int k = layout.add(m);
      ++merges;
      around.clear();
      layout.side_neighbours(k, around);
      for (int n : around) offer(k, n);
    }
    if (!freed_limited) break;
    const std::vector<int> all = layout.brick_ids();
    std::fill(seed.begin(), seed.end(), 0);
    seed.resize(layout.id_limit(), 0);
    for (int id : all) seed[id] = 1;
    offer_all(all, true);
    if (pool.empty()) break;
  }
  if (own_edit) layout.commit();
  return merges;
}

}  // namespace lego::layout
