#pragma once
// Merging bricks (paper section 4): two bricks merge when their union is a brick of the family
// and the color assignment rule allows it; Algorithm 4 merges at random until nothing can.
#include <algorithm>
#include <optional>
#include <set>
#include <span>
#include <utility>
#include <vector>

#include "core/random.h"
#include "layout/layout.h"
#include "layout/limits.h"

namespace lego::layout {

// Footprints (length >= width) the layout may use.
using Family = std::vector<std::pair<int, int>>;
// 1x1, 1x2, 1x3, 1x4, 1x6, 1x8, 2x2, 2x3, 2x4, 2x6 and 2x8 (paper section 3).
const Family& standard_family();

enum class ColorRule {
  Hard,  // bricks of two different colors never merge
  Soft,  // they may, by importance sampling (p_i, p_j), or the merge is discarded (p_d)
};

// Colours that may stand in for each other under the hard rule: pairs of LDraw codes within a
// colour distance. legolize gives them to the refinement only: the first layout keeps every colour
// exact, and the refinement reconfigures only around the weakest contacts, so that colour fidelity
// is traded only where it breaks structure.
struct ColorTrades {
  std::set<std::pair<int, int>> close;  // (a, b) with a < b
  // Every pair of `codes` within `max_distance` (CIEDE2000, of the colour table's colours).
  static ColorTrades within(const std::vector<int>& codes, double max_distance);
  bool allowed(int a, int b) const { return close.contains({std::min(a, b), std::max(a, b)}); }
};

struct MergeRules {
  ColorRule color = ColorRule::Hard;
  ColorTrades trades;  // hard rule: colours that may merge all the same
  double w_c = 1;      // soft rule: the weight of discarding; large w_c approaches the hard rule
  Limits limits;
  // How strongly a pop favours pairs that make small bricks: a pair making a brick of area A is
  // drawn with weight A^-small_first. 0 is the paper's uniform pop; 2 leaves a quarter fewer
  // 1x1 bricks on a hollow sphere (measured: docs/layout.md) and every maximal layout stays
  // reachable.
  double small_first = 2;
  Family family = standard_family();
};

// The brick a and b make together if their union is a family brick in one layer; its color by
// the paper's cases 1-3, or a's color in case 4 (two colors: see random_merge). Limits are not
// checked here.
std::optional<LayoutBrick> merged_shape(const Layout& layout, int a, int b, const Family& family);
// Whether a and b can merge under the rules: shape, color rule (hard: cases 1-3 only) and limits.
// Deterministic; the soft rule's random discard (p_d) comes on top in random_merge.
bool mergeable(const Layout& layout, int a, int b, const MergeRules& rules);
// The merged brick when a and b are mergeable (its color a's in case 4, to be drawn), else none.
std::optional<LayoutBrick> merge_of(const Layout& layout, int a, int b, const MergeRules& rules);

// Algorithm 4 (and the remerge of Algorithm 2): every mergeable pair with a brick among `seeds`
// goes into a list; pairs are popped at random and merged, and the merged brick's pairs are
// appended, until the list is empty. Returns the number of merges.
size_t random_merge(Layout& layout, std::span<const int> seeds, const MergeRules& rules,
                    Random& rng);

// The voxels of `brick` whose target color is a color other than its own.
int color_mismatches(const Layout& layout, const LayoutBrick& brick);

// How far a layout's colours are from its target's: the visible voxels (those with a colour of
// their own) and those built in another colour, with the CIEDE2000 distances between the two.
struct ColorChanges {
  size_t visible = 0, changed = 0;
  double mean_distance = 0, max_distance = 0;  // over the changed voxels
};
ColorChanges color_changes(const Layout& layout);

}  // namespace lego::layout
