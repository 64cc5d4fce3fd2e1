#include "layout/layout.h"

#include <algorithm>
#include <cassert>
#include <stdexcept>

namespace lego::layout {

namespace {

uint64_t footprint_key(int length, int width) {
  return (uint64_t(length) << 8 | uint64_t(width)) << 32;
}
uint64_t color_key(int length, int width, int color) {
  // Colors (LDraw codes, direct colors 0x2RRGGBB, kIgnore) fit in 31 bits plus a flag.
  return footprint_key(length, width) | (uint64_t(uint32_t(color)) & 0x7fffffffu) | 1ull << 31;
}

}  // namespace

Layout::Layout(Target target) : target_(std::move(target)) {
  owner_.assign(target_.color.size(), -1);
  for (int y = 0; y < height(); ++y)
    for (int z = 0; z < depth(); ++z)
      for (int x = 0; x < width(); ++x) {
        const int c = target_.at(x, y, z);
        if (c != kEmpty) add(LayoutBrick{.x = x, .y = y, .z = z, .color = c});
      }
}

int Layout::grow(int x, int y, int z, int color) {
  target_.set(x, y, z, color);
  return add(LayoutBrick{.x = x, .y = y, .z = z, .color = color});
}

int Layout::grow(const LayoutBrick& brick) {
  for (int z = brick.z; z < brick.max_z(); ++z)
    for (int x = brick.x; x < brick.max_x(); ++x) target_.set(x, brick.y, z, brick.color);
  return add(brick);
}

std::vector<int> Layout::brick_ids() const {
  std::vector<int> ids;
  ids.reserve(alive_);
  for (size_t i = 0; i < bricks_.size(); ++i)
    if (bricks_[i].alive) ids.push_back(int(i));
  return ids;
}

void Layout::side_neighbours(int id, std::vector<int>& out) const {
  const LayoutBrick& b = bricks_[id];
  ++stamp_;
  mark_.resize(bricks_.size(), 0);
  auto take = [&](int x, int z) {
    const int n = brick_at(x, b.y, z);
    if (n >= 0 && mark_[n] != stamp_) {
      mark_[n] = stamp_;
      out.push_back(n);
    }
  };
  for (int x = b.x; x < b.max_x(); ++x) {
    take(x, b.z - 1);
    take(x, b.max_z());
  }
  for (int z = b.z; z < b.max_z(); ++z) {
    take(b.x - 1, z);
    take(b.max_x(), z);
  }
}

void Layout::snapped_neighbours(int id, std::vector<int>& out) const {
  const LayoutBrick& b = bricks_[id];
  ++stamp_;
  mark_.resize(bricks_.size(), 0);
  for (int y : {b.y - 1, b.y + 1})
    for (int z = b.z; z < b.max_z(); ++z)
      for (int x = b.x; x < b.max_x(); ++x) {
        const int n = brick_at(x, y, z);
        if (n >= 0 && mark_[n] != stamp_) {
          mark_[n] = stamp_;
          out.push_back(n);
        }
      }
}

void Layout::neighbours(int id, std::vector<int>& out) const {
  side_neighbours(id, out);
  snapped_neighbours(id, out);  // a brick is never both: different layers
}

std::vector<int> Layout::ring(std::span<const int> seeds, int k) const {
  ring_mark_.resize(bricks_.size(), 0);
  const int seen = ++ring_stamp_;
  std::vector<int> result;
  auto take = [&](int n) {
    if (alive(n) && ring_mark_[n] != seen) {
      ring_mark_[n] = seen;
      result.push_back(n);
    }
  };
  for (int s : seeds) take(s);
  std::vector<int> around;
  for (size_t begin = 0, step = 0; step < size_t(k) && begin < result.size(); ++step) {
    const size_t end = result.size();
    for (size_t i = begin; i < end; ++i) {
      around.clear();
      neighbours(result[i], around);
      for (int n : around) take(n);
    }
    begin = end;
  }
  return result;
}

int Layout::add(const LayoutBrick& brick) {
  int id;
  if (!free_.empty()) {
    id = free_.back();
    free_.pop_back();
  } else {
    id = int(bricks_.size());
    bricks_.emplace_back();
  }
  bricks_[id] = brick;
  bricks_[id].alive = true;
  place(id);
  if (editing_) added_.push_back(id);
  return id;
}

void Layout::remove(int id) {
  assert(alive(id));
  if (editing_) removed_.emplace_back(id, bricks_[id]);
  unplace(id);
  if (!editing_) free_.push_back(id);
}

void Layout::place(int id) {
  LayoutBrick& b = bricks_[id];
  b.alive = true;
  for (int z = b.z; z < b.max_z(); ++z)
    for (int x = b.x; x < b.max_x(); ++x) {
      int& o = owner_[target_.index(x, b.y, z)];
      if (o != -1 || target_.at(x, b.y, z) == kEmpty)
        throw std::logic_error("Layout::add: a brick over a filled or empty voxel");
      o = id;
    }
  ++alive_;
  tally(b, +1);
}

void Layout::unplace(int id) {
  LayoutBrick& b = bricks_[id];
  for (int z = b.z; z < b.max_z(); ++z)
    for (int x = b.x; x < b.max_x(); ++x) owner_[target_.index(x, b.y, z)] = -1;
  b.alive = false;
  --alive_;
  tally(b, -1);
}

void Layout::tally(const LayoutBrick& b, int delta) {
  counts_[footprint_key(b.length(), b.width())] += delta;
  counts_[color_key(b.length(), b.width(), b.color)] += delta;
}

int Layout::count(int length, int width, int color) const {
  auto it = counts_.find(color_key(length, width, color));
  return it == counts_.end() ? 0 : it->second;
}

int Layout::count(int length, int width) const {
  auto it = counts_.find(footprint_key(length, width));
  return it == counts_.end() ? 0 : it->second;
}

void Layout::begin_edit() {
  if (editing_) throw std::logic_error("Layout::begin_edit: an edit is already open");
  editing_ = true;
  removed_.clear();
  added_.clear();
}

void Layout::commit() {
  editing_ = false;
  for (const auto& [id, brick] : removed_)
    if (!bricks_[id].alive) free_.push_back(id);
  removed_.clear();
  added_.clear();
}

Edit Layout::open_edit() const {
  Edit e;
  std::vector<int> added = added_;
  std::sort(added.begin(), added.end());
  for (const auto& [id, brick] : removed_)
    if (!std::binary_search(added.begin(), added.end(), id)) e.removed.push_back(id);
  for (int id : added_)
    if (bricks_[id].alive) e.added.push_back(bricks_[id]);
  return e;
}

void Layout::apply(const Edit& e) {
  for (int id : e.removed) remove(id);
  for (const LayoutBrick& b : e.added) add(b);
}

void Layout::rollback() {
  editing_ = false;
  // Ids removed within an edit are not reused within it, so each removed id either lived before
  // the edit (restore it) or was added by it (it stays dead).
  std::vector<int> added = added_;
  std::sort(added.begin(), added.end());
  for (int id : added_) {
    if (bricks_[id].alive) unplace(id);
    free_.push_back(id);
  }
  for (auto& [id, brick] : removed_) {
    if (std::binary_search(added.begin(), added.end(), id)) continue;
    bricks_[id] = brick;
    place(id);
  }
  removed_.clear();
  added_.clear();
}

}  // namespace lego::layout
