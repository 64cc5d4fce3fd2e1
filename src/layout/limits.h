#pragma once
// Brick limits (paper section 7): how many bricks of a size, or of a size in one color, a layout
// may use. Merges that would exceed a limit are discarded.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "core/brick_catalog.h"
#include "layout/layout.h"

namespace lego::layout {

// An inventory is a list of parts: 16 MB is some 500,000 lines.
inline constexpr std::uintmax_t kMaxInventoryBytes = 16u << 20;

struct Limits {
  std::map<std::pair<int, int>, int> by_size;              // (length, width) -> most bricks
  std::map<std::tuple<int, int, int>, int> by_size_color;  // (length, width, LDraw color)
  // The color IGNORE bricks are built in, so that they count against its limits.
  int inside_color = 72;
  int support_color = kDefaultSupportColor;  // and supports in this one
  // Set by an inventory: a size and color it does not list may not be used at all.
  bool listed_only = false;

  // Whether some limit counts bricks of this size (in any color).
  bool limits_size(int length, int width) const;
  bool empty() const { return by_size.empty() && by_size_color.empty(); }
  // Whether adding `brick` to the layout keeps every limit.
  bool allow(const Layout& layout, const LayoutBrick& brick) const;
  // The limits the layout exceeds, in words ("1x1 in color 4: 120 used, limit 100").
  std::vector<std::string> exceeded(const Layout& layout) const;
  // Takes off every limit what `layout` uses, so that the next layout (another piece of the same
  // model) gets what is left.
  void use_up(const Layout& layout);

  // "2x4:100", "2x8:0", "3001@14:50", "1x2@4:10": a size (either order) or an LDraw brick part
  // number, optionally @color, then the most bricks. Throws InputError naming `origin`.
  void add(std::string_view spec, const BrickCatalog& catalog, std::string_view origin = "--limit");
  // An inventory CSV: part,color,quantity per line (a header line and # comments are skipped;
  // an empty color means any color), a regular file of at most kMaxInventoryBytes. Throws
  // InputError with file:line.
  void read_inventory(const std::filesystem::path& csv, const BrickCatalog& catalog);

 private:
  // Bricks of this size that are built in `color` without being counted in it: IGNORE bricks in
  // the inside colour, supports in the support colour.
  int stand_ins(const Layout& layout, int length, int width, int color) const;
};

}  // namespace lego::layout
