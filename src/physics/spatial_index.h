#pragma once
// The contact graph's spatial indexes (ContactGraph::build): receptacles by where they are and
// which way they face, and body boxes by the cells they cover. Both answer "what is here" in time
// independent of the model's size.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "physics/world_shape.h"

namespace lego::physics {

// A coordinate as a whole number of kSnap steps.
inline int64_t snap_steps(double v) {
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
inline PointKey key_of(const Vec3& p, int direction) {
  return {snap_steps(p[0]), snap_steps(p[1]), snap_steps(p[2]), direction};
}

// PointKey -> a whole number, by open addressing in one array: std::unordered_map allocated a
// node per key, and a town's receptacles took a tenth of its contact graph's time to index.
class PointTable {
 public:
  // The value at `key`, set to `value` where there was none; whether it was set.
  std::pair<int*, bool> try_emplace(const PointKey& key, int value) {
    if (4 * (used_ + 1) > 3 * slots_.size()) grow();
    Slot* s = &slots_[start(key)];
    for (size_t mask = slots_.size() - 1; s->value >= 0;
         s = &slots_[size_t(s - slots_.data() + 1) & mask])
      if (s->x == key.x && s->y == key.y && s->z == key.z && s->direction == key.direction)
        return {&s->value, false};
    *s = {key.x, key.y, key.z, key.direction, value};
    ++used_;
    return {&s->value, true};
  }
  // The value at `key`, or -1.
  int find(const PointKey& key) const {
    if (slots_.empty()) return -1;
    const size_t mask = slots_.size() - 1;
    for (size_t i = start(key);; i = (i + 1) & mask) {
      const Slot& s = slots_[i];
      if (s.value < 0) return -1;
      if (s.x == key.x && s.y == key.y && s.z == key.z && s.direction == key.direction)
        return s.value;
    }
  }
  void reserve(size_t n) {
    while (4 * n > 3 * slots_.size()) grow();
  }

 private:
  struct Slot {
    int64_t x, y, z;
    int direction, value;  // value -1: an empty slot
  };
  std::vector<Slot> slots_;
  size_t used_ = 0;

  size_t start(const PointKey& key) const {
    const uint64_t h = uint64_t(PointKeyHash{}(key)) * 0x9E3779B97F4A7C15ull;
    return size_t(h >> 32) & (slots_.size() - 1);
  }
  void grow() {
    std::vector<Slot> old(std::max<size_t>(16, 2 * slots_.size()), Slot{0, 0, 0, 0, -1});
    old.swap(slots_);
    used_ = 0;
    for (const Slot& s : old)
      if (s.value >= 0) try_emplace({s.x, s.y, s.z, s.direction}, s.value);
  }
};

// Every receptacle of the assembly by position and facing; duplicates chain through `next`.
class ReceptacleIndex {
 public:
  struct Entry {
    Vec3 at;
    int direction, brick, next;
  };
  void add(const Connector& c, int brick) {
    const int index = int(entries_.size());
    auto [first, inserted] = first_.try_emplace(key_of(c.at, c.direction), index);
    entries_.push_back({c.at, c.direction, brick, inserted ? -1 : *first});
    if (!inserted) *first = index;
  }
  // The first entry at p facing `direction`, or -1; follow Entry::next for the others.
  int find(const Vec3& p, int direction) const { return first_.find(key_of(p, direction)); }
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
  PointTable first_;
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
    // A run of cells along z is one stretch of the sorted list: one search each.
    int64_t lo[3], hi[3];
    range(b, margin, lo, hi);
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y) {
        const uint64_t first = key(x, y, lo[2]), last = key(x, y, hi[2]);
        auto it =
            std::lower_bound(cells_.begin(), cells_.end(), std::pair<uint64_t, int>(first, -1));
        for (; it != cells_.end() && it->first <= last; ++it) f(it->second);
      }
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
        for (int64_t z = lo[2]; z <= hi[2]; ++z) f(key(x, y, z));
  }
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (uint64_t(x + kOffset) << 42) | (uint64_t(y + kOffset) << 21) | uint64_t(z + kOffset);
  }
};

}  // namespace lego::physics
