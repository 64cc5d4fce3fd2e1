// Layouts (paper sections 4 and 5): exact, maximal, color-true, within limits, one component.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

#include "core/error.h"
#include "layout/components.h"
#include "layout/pieces.h"
#include "layout/reconfigure.h"
#include "layout/targets.h"
#include "layout/to_assembly.h"
#include "physics/connectivity.h"
#include "physics/contact_graph.h"
#include "physics/stability.h"
#include "test_paths.h"

using namespace lego;
using namespace lego::layout;

namespace {

// Every non-empty voxel covered by exactly one brick, no brick over an empty voxel; checked
// from the bricks' rectangles, not from the layout's own map.
void expect_exact(const Layout& l) {
  const Target& t = l.target();
  std::vector<int> cover(t.color.size(), 0);
  for (int id : l.brick_ids()) {
    const LayoutBrick& b = l.brick(id);
    for (int z = b.z; z < b.max_z(); ++z)
      for (int x = b.x; x < b.max_x(); ++x) {
        ASSERT_TRUE(t.contains(x, b.y, z));
        ++cover[t.index(x, b.y, z)];
        ASSERT_EQ(l.brick_at(x, b.y, z), id);
      }
  }
  for (size_t i = 0; i < cover.size(); ++i) ASSERT_EQ(cover[i], t.color[i] == kEmpty ? 0 : 1) << i;
}

bool in_family(int a, int b) {
  const auto& f = standard_family();
  return std::find(f.begin(), f.end(), std::pair{std::max(a, b), std::min(a, b)}) != f.end();
}

// No two bricks of a layer form a family brick together with compatible colors (hard rule).
// Brute force over pairs: the union is a brick when its bounding box has exactly their area.
void expect_maximal(const Layout& l, const Limits& limits = {}) {
  std::map<int, std::vector<int>> layers;
  for (int id : l.brick_ids()) layers[l.brick(id).y].push_back(id);
  for (auto& [y, ids] : layers)
    for (size_t i = 0; i < ids.size(); ++i)
      for (size_t j = i + 1; j < ids.size(); ++j) {
        const LayoutBrick &p = l.brick(ids[i]), &q = l.brick(ids[j]);
        const int x0 = std::min(p.x, q.x), x1 = std::max(p.max_x(), q.max_x());
        const int z0 = std::min(p.z, q.z), z1 = std::max(p.max_z(), q.max_z());
        if ((x1 - x0) * (z1 - z0) != p.voxels() + q.voxels()) continue;
        if (!in_family(x1 - x0, z1 - z0)) continue;
        if (p.color != kIgnore && q.color != kIgnore && p.color != q.color) continue;
        LayoutBrick m{.x = x0, .y = y, .z = z0, .size_x = x1 - x0, .size_z = z1 - z0};
        m.color = p.color == kIgnore ? q.color : p.color;
        if (!limits.allow(l, m)) continue;
        ADD_FAILURE() << "bricks " << ids[i] << " and " << ids[j] << " of layer " << y
                      << " could merge";
        return;
      }
}

// Hard colors: a brick's voxels ask for its color or for none.
void expect_color_true(const Layout& l) {
  for (int id : l.brick_ids()) {
    const LayoutBrick& b = l.brick(id);
    std::set<int> wanted;
    for (int z = b.z; z < b.max_z(); ++z)
      for (int x = b.x; x < b.max_x(); ++x)
        if (int c = l.target().at(x, b.y, z); c != kIgnore) wanted.insert(c);
    ASSERT_LE(wanted.size(), 1u);
    if (!wanted.empty()) {
      ASSERT_EQ(b.color, *wanted.begin());
    }
  }
}

int total_mismatches(const Layout& l) {
  int e = 0;
  for (int id : l.brick_ids()) e += color_mismatches(l, l.brick(id));
  return e;
}

// Components counted independently: the physics' connectivity over the assembly's contacts.
int physics_components(const Layout& l) {
  auto la = to_assembly(l, BrickCatalog::standard(), 72);
  auto graph = physics::ContactGraph::build(la.assembly, physics::GroundMode::Table);
  return physics::analyze_connectivity(int(la.assembly.bricks.size()), graph).component_count;
}

std::vector<LayoutBrick> snapshot(const Layout& l) {
  std::vector<LayoutBrick> out;
  for (int id : l.brick_ids()) out.push_back(l.brick(id));
  std::sort(out.begin(), out.end(),
            [](auto& a, auto& b) { return std::tie(a.y, a.z, a.x) < std::tie(b.y, b.z, b.x); });
  return out;
}

bool same(const std::vector<LayoutBrick>& a, const std::vector<LayoutBrick>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](auto& p, auto& q) {
    return std::tie(p.x, p.y, p.z, p.size_x, p.size_z, p.color) ==
           std::tie(q.x, q.y, q.z, q.size_x, q.size_z, q.color);
  });
}

}  // namespace

TEST(Layout, StartsWithOneUnitBrickPerVoxel) {
  Target t = test::random_target(7, 3, 5, 0.6, 2, 1);
  Layout l(t);
  EXPECT_EQ(l.brick_count(), t.filled());
  expect_exact(l);
  EXPECT_EQ(l.count(1, 1), int(t.filled()));
}

TEST(Layout, RingsGrowThroughFacesAndSnaps) {
  // A solid 5x3x5 block of 1x1 bricks: the 1-ring of the centre is its 6 face neighbours, the
  // 2-ring everything within Manhattan distance 2 (inside the block).
  Target t(5, 3, 5);
  std::fill(t.color.begin(), t.color.end(), kIgnore);
  Layout l(t);
  const int centre = l.brick_at(2, 1, 2);
  EXPECT_EQ(l.ring(std::span(&centre, 1), 0).size(), 1u);
  EXPECT_EQ(l.ring(std::span(&centre, 1), 1).size(), 7u);
  // Manhattan ball of radius 2 in 3D has 25 points; y is limited to 0..2, cutting the 2 at y=±2.
  EXPECT_EQ(l.ring(std::span(&centre, 1), 2).size(), 23u);
}

TEST(Layout, RollbackRestoresTheLayoutExactly) {
  Layout l(test::random_target(12, 4, 9, 0.8, 3, 5));
  Random rng(3);
  random_merge(l, l.brick_ids(), {}, rng);
  const auto before = snapshot(l);
  const auto counts_before = l.count(4, 2);
  for (int k = 1; k <= 3; ++k) {
    l.begin_edit();
    const int seed = l.brick_ids()[rng.below(l.brick_count())];
    reconfigure(l, std::span(&seed, 1), k, {}, rng);
    l.rollback();
    expect_exact(l);
    EXPECT_TRUE(same(snapshot(l), before));
    EXPECT_EQ(l.count(4, 2), counts_before);
  }
}

TEST(Layout, RandomMergeIsExactMaximalAndColorTrue) {
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    SCOPED_TRACE(seed);
    Layout l(test::random_target(6 + int(seed % 7), 1 + int(seed % 4), 5 + int(seed % 5),
                                 0.4 + 0.02 * double(seed), int(seed % 4), seed));
    Random rng(seed);
    random_merge(l, l.brick_ids(), {}, rng);
    expect_exact(l);
    expect_maximal(l);
    expect_color_true(l);
    EXPECT_EQ(total_mismatches(l), 0);
  }
}

TEST(Layout, ReconfigurationKeepsTheLayoutExactMaximalAndColorTrue) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE(seed);
    Layout l(test::random_target(10, 4, 8, 0.7, 2, seed));
    Random rng(seed);
    random_merge(l, l.brick_ids(), {}, rng);
    for (int step = 0; step < 10; ++step) {
      l.begin_edit();
      const int critical = l.brick_ids()[rng.below(l.brick_count())];
      reconfigure(l, std::span(&critical, 1), 1 + step % 3, {}, rng);
      l.commit();
    }
    expect_exact(l);
    expect_maximal(l);
    expect_color_true(l);
  }
}

TEST(Layout, SoftColorsMismatchLessAsWcGrows) {
  // Stripes of two colors one voxel wide: the hard rule leaves mostly 1xN bricks along them;
  // the soft rule trades color for bigger bricks, less so as w_c grows.
  Target t(24, 4, 24);
  for (int y = 0; y < 4; ++y)
    for (int z = 0; z < 24; ++z)
      for (int x = 0; x < 24; ++x) t.set(x, y, z, (x + z) % 2 ? 4 : 1);
  std::vector<double> mismatches;
  for (double w_c : {0.01, 0.3, 3.0, 1000.0}) {
    double sum = 0;
    for (uint64_t seed = 1; seed <= 5; ++seed) {
      Layout l(t);
      Random rng(seed);
      MergeRules rules;
      rules.color = ColorRule::Soft;
      rules.w_c = w_c;
      random_merge(l, l.brick_ids(), rules, rng);
      expect_exact(l);
      sum += total_mismatches(l);
    }
    mismatches.push_back(sum / 5);
  }
  for (size_t i = 1; i < mismatches.size(); ++i)
    EXPECT_LT(mismatches[i], mismatches[i - 1]) << "w_c step " << i;
  EXPECT_GT(mismatches.front(), 100);  // the soft rule really did merge across colors
  EXPECT_LT(mismatches.back(), 25);    // a large w_c nearly the hard rule (1% of 2,304 voxels)
}

TEST(Layout, LimitsAreNeverExceeded) {
  Limits limits;
  const auto& catalog = BrickCatalog::standard();
  limits.add("2x4:5", catalog);
  limits.add("8x2:0", catalog);
  limits.add("3001@4:2", catalog);  // 2x4 in red
  limits.add("1x6@72:3", catalog);  // the inside color counts IGNORE bricks
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE(seed);
    Layout l(test::random_target(16, 3, 16, 0.9, 2, seed));
    Random rng(seed);
    MergeRules rules;
    rules.limits = limits;
    initialize_layout(l, rules, rng);
    EXPECT_LE(l.count(4, 2), 5);
    EXPECT_EQ(l.count(8, 2), 0);
    EXPECT_LE(l.count(4, 2, 4), 2);
    EXPECT_LE(l.count(6, 1, 72) + l.count(6, 1, kIgnore), 3);
    EXPECT_TRUE(limits.exceeded(l).empty());
    expect_exact(l);
    expect_maximal(l, limits);
  }
}

TEST(Layout, LimitSpecsAndInventories) {
  const auto& catalog = BrickCatalog::standard();
  Limits limits;
  limits.add("4x2:7", catalog);
  limits.add("3004@14:9", catalog);
  EXPECT_EQ((limits.by_size.at({4, 2})), 7);
  EXPECT_EQ((limits.by_size_color.at({2, 1, 14})), 9);
  for (const char* bad :
       {"2x4", "2x4:-1", "9x9x:3", "3024:5" /* a plate */, "3001@nope:4", "2x4:many", "nopart:3"})
    EXPECT_THROW(limits.add(bad, catalog), InputError) << bad;

  auto csv = test::scratch("layout_", "inventory.csv");
  std::ofstream(csv) << "part,color,quantity\n3001,4,10\n# a comment\n1x1,,500\n\n3003,1,2\n";
  Limits inventory;
  inventory.read_inventory(csv, catalog);
  EXPECT_TRUE(inventory.listed_only);
  EXPECT_EQ((inventory.by_size_color.at({4, 2, 4})), 10);
  EXPECT_EQ((inventory.by_size.at({1, 1})), 500);
  // Unlisted sizes and colors may not be used at all.
  Layout l(Target(4, 1, 4));
  EXPECT_FALSE(inventory.allow(l, LayoutBrick{.size_x = 4, .size_z = 2, .color = 1}));
  EXPECT_TRUE(inventory.allow(l, LayoutBrick{.size_x = 4, .size_z = 2, .color = 4}));
  EXPECT_TRUE(inventory.allow(l, LayoutBrick{.size_x = 1, .size_z = 1, .color = 1}));

  std::ofstream(csv) << "3001,4,10\n3001,4\n";
  try {
    Limits bad;
    bad.read_inventory(csv, catalog);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
  }
  // A device never ends, a folder is no list: refused before reading (/dev/zero filled the
  // memory); so is a file too large to be an inventory.
  for (const std::filesystem::path& not_a_list :
       {std::filesystem::path("/dev/zero"), csv.parent_path()}) {
    Limits refused;
    EXPECT_THROW(refused.read_inventory(not_a_list, catalog), InputError) << not_a_list;
  }
  std::filesystem::resize_file(csv, kMaxInventoryBytes + 1);
  Limits huge;
  EXPECT_THROW(huge.read_inventory(csv, catalog), InputError);
}

TEST(Layout, OneComponentForSphereTorusAndJoinedTowers) {
  struct Case {
    const char* name;
    Target target;
  };
  std::vector<Case> cases{{"sphere", test::hollow_sphere(10, 3, 4)},
                          {"torus", test::torus(9, 3)},
                          {"towers", test::two_towers(2, 8, 2, true)}};
  int needed_algorithm_5 = 0;
  for (auto& c : cases)
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      SCOPED_TRACE(std::string(c.name) + " seed " + std::to_string(seed));
      Layout l(c.target);
      Random rng(seed);
      const ConnectResult r = initialize_layout(l, {}, rng);
      EXPECT_TRUE(r.single) << r.components << " components";
      EXPECT_EQ(r.components, 1);
      EXPECT_EQ(physics_components(l), 1);
      expect_exact(l);
      expect_maximal(l);
      expect_color_true(l);
      needed_algorithm_5 += r.components_start > 1;
    }
  // The random merge alone left several components at least once, so Algorithm 5 did work here.
  EXPECT_GT(needed_algorithm_5, 0);
}

TEST(Layout, SeparateObjectsEndInNoSolution) {
  Layout l(test::two_towers(2, 4, 3, false));
  Random rng(1);
  int calls = 0;
  ConnectOptions options;
  options.progress = [&](int, int, int) { ++calls; };
  const ConnectResult r = initialize_layout(l, {}, rng, options);
  EXPECT_FALSE(r.single);
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.iterations, options.fail_max);  // gave up after fail_MAX tries, never accepted
  EXPECT_EQ(calls, r.iterations);
  expect_exact(l);
}

TEST(Layout, AFloatingBrickCountsWhateverItsIdWithTheGroundJoining) {
  // A brick high above a column, made first (id 0) by a layout of its own voxel order: with the
  // ground joining what stands on it, the floating brick is still its own component (it was
  // once left out when it was the first brick not on the ground).
  Target t(3, 4, 1);
  t.set(0, 0, 0, 4);
  t.set(0, 1, 0, 4);
  t.set(2, 3, 0, 4);
  Layout l(t);
  // Ids follow the voxel order (y, z, x), so the floating brick comes last; freed ids are
  // reused last-freed first, so remove it and then the column, and add it back first.
  const int floating = l.brick_at(2, 3, 0), low = l.brick_at(0, 0, 0), high = l.brick_at(0, 1, 0);
  l.remove(floating);
  l.remove(high);
  l.remove(low);
  l.add(LayoutBrick{.x = 2, .y = 3, .z = 0, .color = 4});
  l.add(LayoutBrick{.x = 0, .y = 0, .z = 0, .color = 4});
  l.add(LayoutBrick{.x = 0, .y = 1, .z = 0, .color = 4});
  ASSERT_LT(l.brick_at(2, 3, 0), l.brick_at(0, 0, 0));
  Random rng(1);
  const ComponentAnalysis c = analyze_components(l, rng, true);
  EXPECT_EQ(c.count, 2);
  EXPECT_NE(c.component[size_t(l.brick_at(2, 3, 0))], -1);
  EXPECT_NE(c.component[size_t(l.brick_at(2, 3, 0))], c.component[size_t(l.brick_at(0, 0, 0))]);
}

TEST(Layout, ScenesSplitIntoPiecesAndThinSpansAreJoined) {
  // Two towers on the ground and a block floating above the gap between them.
  Target t(12, 10, 2);
  for (int y = 0; y < 4; ++y)
    for (int z = 0; z < 2; ++z) {
      t.set(0, y, z, 4);
      t.set(11, y, z, 1);
    }
  for (int y = 7; y < 9; ++y)
    for (int x = 4; x < 8; ++x)
      for (int z = 0; z < 2; ++z) t.set(x, y, z, 14);
  const std::vector<Piece> pieces = split_pieces(t);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_TRUE(pieces[0].grounded());
  EXPECT_EQ(pieces[0].objects, 2);
  EXPECT_EQ(pieces[0].voxels, 16u);
  EXPECT_EQ(pieces[1].lift, 7);
  EXPECT_EQ(pieces[1].objects, 1);
  EXPECT_EQ(pieces[1].target.height, 3);
  EXPECT_EQ(pieces[1].target.at(4, 0, 0), 14);  // lowered to stand on its own bottom
  EXPECT_EQ(pieces[1].target.filled(), 16u);

  // Two towers joined at the top by a one-voxel beam 18 long, one layer thick: no brick is that
  // long, so some part of the beam hangs between bricks and only added voxels join it.
  Target span(26, 6, 1);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 4; ++x) {
      span.set(x, y, 0, 4);
      span.set(25 - x, y, 0, 4);
    }
  for (int x = 4; x < 22; ++x) span.set(x, 5, 0, 4);
  ConnectOptions options;
  options.ground_connects = true;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    Random rng(seed);
    const JoinedLayout j = initialize_joined(span, {}, rng, options);
    EXPECT_GT(j.pieces_before, 1);
    EXPECT_TRUE(j.connect.single);
    EXPECT_GT(j.voxels_added, 0u);
    EXPECT_EQ(j.layout->target().filled(), span.filled() + j.voxels_added);
    expect_exact(*j.layout);
    // The added voxels are below the beam (the grid has no layer above it), in its colour.
    for (int x = 0; x < 26; ++x) {
      if (span.at(x, 4, 0) == kEmpty && j.layout->target().at(x, 4, 0) != kEmpty) {
        EXPECT_EQ(j.layout->target().at(x, 4, 0), 4);
      }
    }
  }
}

TEST(Layout, ObjectsInTheAirStandOnColumnsDownToWhatIsUnderThem) {
  // A slab on the ground, a block in the air over its middle, and a bar in the air beside it.
  Target t(20, 10, 8);
  for (int y = 0; y < 2; ++y)
    for (int z = 0; z < 8; ++z)
      for (int x = 0; x < 10; ++x) t.set(x, y, z, 4);
  for (int y = 5; y < 7; ++y)
    for (int z = 1; z < 7; ++z)
      for (int x = 1; x < 9; ++x) t.set(x, y, z, 14);
  for (int x = 12; x < 20; ++x) t.set(x, 8, 3, 1);  // one voxel thick: columns one voxel square
  const Target before = t;
  const FloatingSupports f = stand_floating_objects(t);
  EXPECT_EQ(f.objects, 2);
  EXPECT_EQ(f.still_floating, 0);
  // Every object reaches the ground now: one piece (the slab with the block on it, and the bar).
  const std::vector<Piece> pieces = split_pieces(t);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0].objects, 2);
  // Nothing the mesh had changed; what was added is support, in columns from the slab's top
  // (layer 2) to the block's bottom (layer 4), and from the ground to the bar (layers 0..7).
  size_t supports = 0;
  for (int y = 0; y < t.height; ++y)
    for (int z = 0; z < t.depth; ++z)
      for (int x = 0; x < t.width; ++x) {
        const int was = before.at(x, y, z), is = t.at(x, y, z);
        if (was != kEmpty) {
          EXPECT_EQ(is, was);
          continue;
        }
        if (is == kEmpty) continue;
        EXPECT_EQ(is, kSupport);
        ++supports;
        if (x < 10) {
          EXPECT_GE(y, 2);
          EXPECT_LE(y, 4);
        } else {
          EXPECT_EQ(z, 3);
          EXPECT_LE(y, 7);
        }
        // Each column reaches from what is under it to the object: full height at its cell.
        const int from = x < 10 ? 2 : 0, to = x < 10 ? 4 : 7;
        for (int h = from; h <= to; ++h) EXPECT_EQ(t.at(x, h, z), kSupport) << x << "," << z;
      }
  EXPECT_EQ(supports, f.voxels);
  // The block (8 x 6) gets two-voxel columns: under its middle and at its far corners, at least
  // kFloatingColumnSpacing apart; the bar, one voxel wide, single ones along its length.
  std::vector<std::pair<int, int>> block_cells, bar_cells;
  for (int z = 0; z < t.depth; ++z)
    for (int x = 0; x < t.width; ++x)
      if (t.at(x, 3, z) == kSupport) (x < 10 ? block_cells : bar_cells).push_back({x, z});
  EXPECT_EQ(block_cells.size() % 4, 0u);
  EXPECT_GE(block_cells.size(), 4u * 3);  // the middle and two ends at least
  EXPECT_GE(bar_cells.size(), 2u);
  for (size_t a = 0; a < bar_cells.size(); ++a)
    for (size_t b = a + 1; b < bar_cells.size(); ++b)
      EXPECT_GE(std::abs(bar_cells[a].first - bar_cells[b].first), kFloatingColumnSpacing);
  EXPECT_EQ(f.columns, int(block_cells.size() / 4 + bar_cells.size()));
  // A scene with nothing in the air is left as it is.
  Target grounded = before;
  for (int y = 5; y < 9; ++y)
    for (int z = 0; z < 8; ++z)
      for (int x = 0; x < 20; ++x) grounded.set(x, y, z, kEmpty);
  const Target kept = grounded;
  EXPECT_EQ(stand_floating_objects(grounded).objects, 0);
  EXPECT_EQ(grounded.color, kept.color);
}

TEST(Layout, FewUnitBricksOnAHollowedSphere) {
  // Paper case study 7: 1x1 bricks are a few percent of the bricks (and less of the volume).
  Layout l(test::hollow_sphere(15, 3, 15));
  Random rng(7);
  ASSERT_TRUE(initialize_layout(l, {}, rng).single);
  const double share = double(l.count(1, 1)) / double(l.brick_count());
  const double volume = double(l.count(1, 1)) / double(l.target().filled());
  std::cout << "hollow sphere r=15: " << l.brick_count() << " bricks, 1x1: " << l.count(1, 1)
            << " (" << 100 * share << "% of bricks, " << 100 * volume << "% of volume)\n";
  EXPECT_LT(share, 0.05);
  EXPECT_LT(volume, 0.02);
}

TEST(Layout, SameSeedSameLayoutOtherSeedOther) {
  auto run = [](uint64_t seed) {
    Layout l(test::hollow_sphere(8, 2, 4));
    Random rng(seed);
    initialize_layout(l, {}, rng);
    return snapshot(l);
  };
  EXPECT_TRUE(same(run(11), run(11)));
  EXPECT_FALSE(same(run(11), run(12)));
}

TEST(Layout, AssemblyTurnsLayersIntoStepsAndKeepsHandedness) {
  Target t(3, 2, 2);
  t.set(0, 0, 0, 4);  // red at voxel x=0, z=0 on the bottom layer
  t.set(1, 0, 0, kIgnore);
  t.set(2, 1, 1, 1);
  t.set(2, 0, 1, kIgnore);
  Layout l(t);
  const auto la = to_assembly(l, BrickCatalog::standard(), 72);
  ASSERT_EQ(la.assembly.bricks.size(), 4u);
  for (size_t i = 0; i < la.assembly.bricks.size(); ++i) {
    const Brick& b = la.assembly.bricks[i];
    const LayoutBrick& lb = l.brick(la.layout_id[i]);
    EXPECT_EQ(b.source.step, lb.y + 1);
    EXPECT_EQ(b.min.y, lb.y * 3);
    EXPECT_EQ(b.min.z, 1 - lb.z);  // z runs the other way (a half turn about x)
    EXPECT_EQ(b.color, lb.color == kIgnore ? 72 : lb.color);
  }
  // Layers in order: step numbers never decrease.
  for (size_t i = 1; i < la.assembly.bricks.size(); ++i)
    EXPECT_LE(la.assembly.bricks[i - 1].source.step, la.assembly.bricks[i].source.step);
  // Building order: in each layer, bricks resting on the layer below come first.
  Layout towers(test::two_towers(2, 4, 2, true));
  Random rng(2);
  initialize_layout(towers, {}, rng);
  const auto ta = to_assembly(towers, BrickCatalog::standard(), 72);
  for (size_t i = 0; i < ta.assembly.bricks.size(); ++i)
    if (ta.assembly.bricks[i].source.step == 4 &&
        (i == 0 || ta.assembly.bricks[i - 1].source.step != 4)) {
      std::vector<int> below;
      towers.snapped_neighbours(ta.layout_id[i], below);
      EXPECT_FALSE(below.empty()) << "the top layer starts with a brick that rests on nothing";
    }
  Loads loads;
  loads.at_voxels.push_back({0, 1, 0, 5});
  EXPECT_THROW(to_assembly(l, BrickCatalog::standard(), 72, loads), InputError);
}

namespace {

// A wall one voxel thick whose voxels alternate between two close colours (Reddish Brown 70 and
// Dark Brown 308, CIEDE2000 11.3): with exact colours no brick spans two voxels, and the wall is
// columns of 1x1 bricks that nothing ties, its middle ones hanging in the air. Traded colours join
// it where it breaks apart, and the colours that changed are counted.
TEST(Layout, ACheckerboardWallHoldsTogetherByTradingCloseColours) {
  Target wall(8, 6, 1);  // on two feet: its middle hangs between them
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      if (y > 0 || x < 2 || x > 5) wall.set(x, y, 0, (x + y) % 2 ? 70 : 308);
  ConnectOptions connect;
  connect.ground_connects = true;
  connect.fail_max = 20;
  Random exact_rng(1);
  const JoinedLayout exact = initialize_joined(wall, {}, exact_rng, connect, 0);
  EXPECT_FALSE(exact.connect.single);
  EXPECT_EQ(color_changes(*exact.layout).changed, 0u);

  MergeRules rules;
  rules.trades = ColorTrades::within({70, 308, 4}, 12);
  ASSERT_TRUE(rules.trades.allowed(308, 70));
  EXPECT_FALSE(rules.trades.allowed(70, 4)) << "red is no brown";
  Random rng(1);
  const JoinedLayout traded = initialize_joined(wall, rules, rng, connect, 0);
  ASSERT_TRUE(traded.connect.single);
  EXPECT_EQ(traded.voxels_added, 0u);
  const ColorChanges c = color_changes(*traded.layout);
  EXPECT_EQ(c.visible, 44u);
  EXPECT_GT(c.changed, 0u);
  EXPECT_LT(c.changed, 24u);
  EXPECT_NEAR(c.max_distance, 11.3, 0.1);
  for (int id : traded.layout->brick_ids()) {
    const int colour = traded.layout->brick(id).color;
    EXPECT_TRUE(colour == 70 || colour == 308) << colour;
  }
  EXPECT_TRUE(
      physics::analyze_stability(to_assembly(*traded.layout, BrickCatalog::standard(), 72).assembly)
          .stable());
}

}  // namespace
