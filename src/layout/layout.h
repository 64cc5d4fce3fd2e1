#pragma once
// A brick layout over a voxel grid (paper sections 4 and 5): which brick fills each voxel. Voxels
// are one stud by one brick, so a brick is a rectangle of voxels in one layer. Bricks have ids
// that stay valid until they are removed; a voxel -> brick map gives the brick at a voxel in O(1).
#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "layout/target.h"

namespace lego::layout {

struct LayoutBrick {
  int x = 0, y = 0, z = 0;  // minimum voxel; y is the layer
  int size_x = 1, size_z = 1;
  int color = kIgnore;  // an LDraw code, or kIgnore when no voxel of it is visible
  bool alive = false;

  int max_x() const { return x + size_x; }  // exclusive
  int max_z() const { return z + size_z; }
  int voxels() const { return size_x * size_z; }
  // The footprint as the catalog names it: length >= width.
  int length() const { return size_x > size_z ? size_x : size_z; }
  int width() const { return size_x > size_z ? size_z : size_x; }
};

// A change to a layout, replayable: the ids it removed and the bricks it added.
struct Edit {
  std::vector<int> removed;
  std::vector<LayoutBrick> added;
};

class Layout {
 public:
  // One 1x1 brick per non-empty voxel, colored as the target asks (paper Algorithm 3, line 1).
  explicit Layout(Target target);

  const Target& target() const { return target_; }
  int width() const { return target_.width; }
  int height() const { return target_.height; }
  int depth() const { return target_.depth; }

  // The brick filling voxel (x, y, z), or -1 when the voxel is empty or outside the grid.
  int brick_at(int x, int y, int z) const {
    return target_.contains(x, y, z) ? owner_[target_.index(x, y, z)] : -1;
  }
  const LayoutBrick& brick(int id) const { return bricks_[size_t(id)]; }
  bool alive(int id) const { return id >= 0 && size_t(id) < bricks_.size() && bricks_[id].alive; }
  size_t brick_count() const { return alive_; }
  size_t id_limit() const { return bricks_.size(); }  // ids are below this
  std::vector<int> brick_ids() const;                 // the living bricks, by id

  // 1-ring (paper footnote 5): bricks sharing a side face in the same layer, or snapped to it
  // (the layer above or below, footprints overlapping). Appends to `out` without duplicates.
  void neighbours(int id, std::vector<int>& out) const;
  void side_neighbours(int id, std::vector<int>& out) const;  // same layer only
  void snapped_neighbours(int id, std::vector<int>& out) const;
  // The seeds and their k-ring neighbours (k >= 0).
  std::vector<int> ring(std::span<const int> seeds, int k) const;

  // Editing. Every add and remove inside begin_edit()...commit() can be undone by rollback(),
  // in time proportional to the edit: reconfigurations try a change and keep it only if better.
  int add(const LayoutBrick& brick);  // the brick must cover empty cells of the layout only
  // Makes the empty voxel (x, y, z) part of the target, in `color`, filled by a 1x1 brick (not
  // inside an edit): voxels added to join parts (layout/pieces.h).
  int grow(int x, int y, int z, int color);
  // Makes the empty voxels under `brick` part of the target, in its colour, filled by it (not
  // inside an edit): supports (layout/supports.h).
  int grow(const LayoutBrick& brick);
  void remove(int id);
  void begin_edit();
  void commit();
  void rollback();
  bool editing() const { return editing_; }
  // The open edit as a replayable change; apply() makes it again (on the layout as it was when
  // the edit began), e.g. after a rollback. Added bricks may get other ids than the first time.
  Edit open_edit() const;
  void apply(const Edit& edit);

  // How many living bricks have this footprint and color (for brick limits).
  int count(int length, int width, int color) const;
  int count(int length, int width) const;

 private:
  void place(int id);
  void unplace(int id);
  void tally(const LayoutBrick& b, int delta);

  Target target_;
  std::vector<LayoutBrick> bricks_;
  std::vector<int> owner_;  // per voxel: brick id or -1
  std::vector<int> free_;   // dead ids that may be reused (never within an open edit)
  size_t alive_ = 0;
  bool editing_ = false;
  std::vector<std::pair<int, LayoutBrick>> removed_;  // in the open edit, with their ids
  std::vector<int> added_;                            // ids added in the open edit
  std::unordered_map<uint64_t, int> counts_;  // by (length, width, color) and (length, width)
  // Per id scratch stamps: deduplication in neighbours() and membership in ring().
  mutable std::vector<int> mark_, ring_mark_;
  mutable int stamp_ = 0, ring_stamp_ = 0;
};

}  // namespace lego::layout
