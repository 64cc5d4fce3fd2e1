// Placed parts into an Assembly: analysed with their exact pose, carried, or left out with why.
#include <gtest/gtest.h>

#include <set>

#include "ldraw/writer.h"
#include "parts/assembly_builder.h"
#include "test_paths.h"

namespace lego::parts {
namespace {

using ldraw::read_text;

// Five upright 2x4 bricks stacked at z, the first with its top at `top`: enough to outvote a few
// turned parts, so that the model's frame stays the model's.
std::string upright_column(int z, int top) {
  std::string out;
  for (int k = 0; k < 5; ++k)
    out += "1 4 0 " + std::to_string(top - 24 * k) + " " + std::to_string(z) +
           " 1 0 0 0 1 0 0 0 1 3001.dat\n";
  return out;
}

TEST(ToAssembly, TurnsByQuarterTurnsAreOnTheLatticeOtherAnglesOnTheirOwn) {
  ldraw::Model m = read_text(
      "0 t\n"
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"                   // upright
      "1 4 0 -48 0 0 0 1 0 1 0 -1 0 0 3001.dat\n"                  // turned 90 degrees
      "1 4 5 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"                   // 5 LDU off: analysed
      "1 4 0 -24 0 1 0 0 0 -1 0 0 0 -1 3001.dat\n"                 // upside down: analysed
      "1 4 0 -24 0 0 1 0 -1 0 0 0 0 1 3001.dat\n"                  // on its side: analysed
      "1 4 0 -24 0 0.57 0 0.82 0 1 0 -0.82 0 0.57 3001.dat\n"      // 55 degrees: own lattice
      "1 4 0 -24 0 2 0 0 0 1 0 0 0 1 3001.dat\n"                   // scaled
      "1 4 0 -24 0 0.9999 0 0.01 0 1 0 -0.01 0 0.9999 3001.dat\n"  // a rotation to 1e-2
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3068b.dat\n",                 // no part file here
      "t.ldr");
  PartLibrary library({}, BrickCatalog::standard());
  auto conv = to_assembly(m, library);
  ASSERT_EQ(conv.assembly.bricks.size(), 7u);
  EXPECT_EQ(conv.brick_part, (std::vector<size_t>{0, 1, 2, 3, 4, 5, 7}));
  // At 55 degrees, on a lattice of its own (docs/what-it-analyses.md, turned lattices): it is
  // carried later if it snaps to nothing there.
  for (size_t b = 0; b < 7; ++b) EXPECT_EQ(bool(conv.assembly.bricks[b].frame), b == 5) << b;
  const Pose at_55 = model_pose(conv.assembly.bricks[5]);
  EXPECT_NEAR(at_55.rotation[2], 0.82, 1e-2);
  EXPECT_EQ(at_55.origin, (Vec3{0, -24, 0}));
  ASSERT_EQ(conv.assembly.carried.size(), 1u);
  EXPECT_EQ(conv.assembly.carried[0].role, PartRole::ScaledOrSheared);
  EXPECT_EQ(conv.assembly.carried[0].mass_g, 2.20);  // carried parts keep their weight
  ASSERT_EQ(conv.skipped.size(), 1u);
  EXPECT_EQ(m.parts[conv.skipped[0].part].line, 10);
  EXPECT_EQ(conv.skipped[0].role, PartRole::UnknownPart);
  EXPECT_NE(conv.skipped[0].reason.find("no part file"), std::string::npos);
  // The near rotation is made exact, with a warning naming its line.
  ASSERT_EQ(conv.diagnostics.size(), 1u);
  EXPECT_EQ(conv.diagnostics[0].line, 9);
  EXPECT_EQ(conv.assembly.bricks[6].pose->rotation,
            (std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
  // Poses are LDraw's own: written back, the bricks land where they were read.
  const auto t = ldraw::brick_transform(conv.assembly.bricks[2], conv.assembly.origin_ldu);
  EXPECT_EQ(t.pos, (std::array<double, 3>{5, -24, 0}));
}

// Inside a submodel turned about the vertical, parts lie on the submodel's lattice: each gets the
// frame of that placement and its exact pose in it, and written back it lands where it was read.
TEST(ToAssembly, PartsOfATurnedSubmodelLieOnItsLattice) {
  ldraw::Model m = read_text(
      "0 FILE main.ldr\n"
      "1 16 10 0 5 0.57 0 0.82 0 1 0 -0.82 0 0.57 stand.ldr\n"
      "1 16 300 0 0 0.57 0 0.82 0 1 0 -0.82 0 0.57 stand.ldr\n" +
          upright_column(400, -24) +
          "0 FILE stand.ldr\n"
          "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
          "1 4 10 -24 0 0 0 1 0 1 0 -1 0 0 3001.dat\n",
      "m.mpd");
  PartLibrary library({}, BrickCatalog::standard());
  auto conv = to_assembly(m, library);
  ASSERT_EQ(conv.assembly.bricks.size(), 9u);  // more upright than turned: the model's frame
  EXPECT_TRUE(conv.assembly.carried.empty());
  std::set<int> frames;
  for (size_t i = 0; i < conv.assembly.bricks.size(); ++i) {
    const Brick& b = conv.assembly.bricks[i];
    const ldraw::PlacedPart& p = m.parts[conv.brick_part[i]];
    if (p.inside < 0) {
      EXPECT_FALSE(b.frame) << p.line;
      continue;
    }
    ASSERT_TRUE(b.frame) << p.line;
    frames.insert(b.frame->id);
    EXPECT_EQ(b.pose->origin, p.local.pos);  // the file's own numbers, on the lattice
    const auto t = ldraw::brick_transform(b, conv.assembly.origin_ldu);
    // To the matrix's two decimals: the frame is the rotation nearest to it.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(t.pos[size_t(k)], p.transform.pos[size_t(k)], 5e-2);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(t.rot[size_t(k)], p.transform.rot[size_t(k)], 1e-2);
  }
  EXPECT_EQ(frames.size(), 2u);  // one lattice per placement
}

// Parts turned one by one on their own lines share an upright lattice where their turns agree up
// to quarter turns, whichever comes first: on its side, upside down or mirrored, each keeps that
// quarter turn on the lattice and lands where it was read. A part tilted on its own line stays
// carried.
TEST(ToAssembly, PartsTurnedOnTheirOwnLinesShareAnUprightLattice) {
  ldraw::Model m = read_text(
      "0 t\n"
      "1 4 0 -24 0 0 -0.866025 0.5 1 0 0 0 0.5 0.866025 3001.dat\n"      // 30 degrees, on its side
      "1 4 40 -48 0 0.866025 0 -0.5 0 -1 0 -0.5 0 -0.866025 3001.dat\n"  // upside down
      "1 4 0 -72 0 -0.866025 0 0.5 0 1 0 0.5 0 0.866025 3001.dat\n"      // mirrored
      "1 4 0 -96 0 0.866025 0 0.5 0 1 0 -0.5 0 0.866025 3001.dat\n"
      "1 4 0 -120 0 1 0 0 0 0.987688 -0.156434 0 0.156434 0.987688 3001.dat\n"  // tilted 9°
          + upright_column(200, 0),  // more upright than turned: the model's frame
      "t.ldr");
  PartLibrary library({}, BrickCatalog::standard());
  auto conv = to_assembly(m, library);
  ASSERT_EQ(conv.assembly.bricks.size(), 9u);
  ASSERT_EQ(conv.assembly.carried.size(), 1u);
  EXPECT_EQ(conv.assembly.carried[0].source.line, 6);
  std::set<int> frames;
  for (size_t i = 0; i < 4; ++i) {
    const Brick& b = conv.assembly.bricks[i];
    ASSERT_TRUE(b.frame) << i;
    EXPECT_FALSE(tilted(*b.frame)) << i;
    frames.insert(b.frame->id);
    const ldraw::PlacedPart& p = m.parts[conv.brick_part[i]];
    const auto t = ldraw::brick_transform(b, conv.assembly.origin_ldu);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(t.pos[size_t(k)], p.transform.pos[size_t(k)], 1e-6);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(t.rot[size_t(k)], p.transform.rot[size_t(k)], 1e-6);
  }
  EXPECT_EQ(frames.size(), 1u);
  EXPECT_FALSE(conv.assembly.bricks[4].frame);
}

// A model drawn turned as a whole (a car tilted by a degree on its springs) is analysed in its own
// frame, with a warning.
TEST(ToAssembly, AModelTurnedAsAWholeIsAnalysedInItsFrame) {
  std::string text =
      "0 FILE tilted.ldr\n0 t\n"
      "1 16 0 0 0 1 0 0 0 0.999848 -0.0174524 0 0.0174524 0.999848 car.ldr\n"
      "0 FILE car.ldr\n";
  for (int k = 0; k < 5; ++k)
    text += "1 4 0 " + std::to_string(-24 * (k + 1)) + " 0 1 0 0 0 1 0 0 0 1 3001.dat\n";
  ldraw::Model m = read_text(text, "tilted.mpd");
  PartLibrary library({}, BrickCatalog::standard());
  auto conv = to_assembly(m, library);
  EXPECT_EQ(conv.assembly.bricks.size(), 5u);
  EXPECT_TRUE(conv.assembly.carried.empty());
  ASSERT_FALSE(conv.diagnostics.empty());
  EXPECT_NE(conv.diagnostics[0].message.find("turned together by 1.0 degrees"), std::string::npos);
}

// A packed MPD's own part blocks belong to it: a library that read another model first, held in
// the same variable (so at the same address), finds the blocks of the model it reads now.
TEST(ToAssembly, EachModelFindsItsOwnEmbeddedParts) {
  auto packed = [](const std::string& block, double half) {
    const std::string h = std::to_string(half);
    return "0 FILE main.ldr\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 " + block + "\n0 FILE " + block +
           "\n0 !LDRAW_ORG Unofficial_Part\n4 16 -" + h + " 0 -" + h + " " + h + " 0 -" + h + " " +
           h + " 0 " + h + " -" + h + " 0 " + h + "\n";
  };
  const std::vector<std::string> texts{packed("one.dat", 10), packed("two.dat", 10),
                                       packed("one.dat", 1e7)};
  PartLibrary shared({}, BrickCatalog::standard());
  ldraw::Model m;
  for (const std::string& text : texts) {
    m = read_text(text, "packed.mpd");
    ASSERT_EQ(m.embedded_parts.size(), 1u);
    const auto seen = to_assembly(m, shared);
    PartLibrary fresh({}, BrickCatalog::standard());
    const auto alone = to_assembly(m, fresh);
    ASSERT_EQ(seen.skipped.size(), alone.skipped.size()) << text;
    for (size_t k = 0; k < seen.skipped.size(); ++k)
      EXPECT_EQ(seen.skipped[k].reason, alone.skipped[k].reason) << text;
    EXPECT_EQ(seen.assembly.bricks.size() + seen.assembly.carried.size(),
              alone.assembly.bricks.size() + alone.assembly.carried.size())
        << text;
  }
}

TEST(ToAssembly, OrthonormalizedAndQuarterTurns) {
  auto r = orthonormalized({0.57, 0, 0.82, 0, 1, 0, -0.82, 0, 0.57}, 1e-2);
  ASSERT_TRUE(r);
  EXPECT_NEAR((*r)[0] * (*r)[0] + (*r)[6] * (*r)[6], 1, 1e-12);
  EXPECT_FALSE(orthonormalized({2, 0, 0, 0, 1, 0, 0, 0, 1}, 1e-2));
  // Two decimals of a turn are within 0.005 of it, their MᵀM 0.013 from I (the corpus's water
  // tower, chapel and shopping centre): within 1e-2 of a rotation, so taken as one. An entry
  // 0.03 off is not.
  for (const std::array<double, 9>& m :
       {std::array<double, 9>{-0.47, 0, -0.89, 0, 1, 0, 0.89, 0, -0.47},
        std::array<double, 9>{0, -0.8, 0.61, 0, 0.61, 0.8, -1, 0, 0},
        std::array<double, 9>{0.973, 0, -0.263, 0, 1, 0, 0.263, 0, 0.973}}) {
    const auto near = orthonormalized(m, 1e-2);
    ASSERT_TRUE(near) << m[0];
    for (size_t k = 0; k < 9; ++k) EXPECT_NEAR((*near)[k], m[k], 1.5e-2) << k;
  }
  EXPECT_FALSE(orthonormalized({0.5, 0, -0.9, 0, 1, 0, 0.87, 0, 0.5}, 1e-2));
  EXPECT_FALSE(quarter_turn(*r, 1e-2));
  auto q = quarter_turn({0, 0, 0.999, 0, -1, 0, 1, 0, 0}, 1e-2);
  ASSERT_TRUE(q);
  EXPECT_EQ(*q, (std::array<double, 9>{0, 0, 1, 0, -1, 0, 1, 0, 0}));
}

// --max-seconds: learning what the parts are stops when the run's budget is spent, saying so.
TEST(ToAssembly, PartKnowledgeStopsWhenTheBudgetIsSpent) {
  const ldraw::Model m = read_text(upright_column(0, 0), "late.ldr");
  PartLibrary library({}, BrickCatalog::standard());
  const Budget spent(0);
  try {
    to_assembly(m, library, {}, &spent);
    ADD_FAILURE() << "went on past a spent budget";
  } catch (const OutOfTime& e) {
    EXPECT_EQ(e.stage(), "part knowledge");
  }
  EXPECT_EQ(to_assembly(m, library).assembly.bricks.size(), 5u);
}

}  // namespace
}  // namespace lego::parts
