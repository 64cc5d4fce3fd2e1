// Parts drawn by eye, taken onto the lattice by the audit's one stage that moves parts.
#include <gtest/gtest.h>

#include <cmath>

#include "ldraw/reader.h"
#include "report/drawn_by_eye.h"

namespace lego::report {
namespace {

using ldraw::read_text;

// An editor's one-LDU nudge: an upright part one LDU above or below the plates the rest of the
// model stands on is taken as on them, with a warning naming its line. Two LDU is a placement of
// its own, and so is one LDU on a part turned on its side (SNOT offsets are the builder's).
TEST(DrawnByEye, AnUprightPartOneLduOffThePlatesIsTakenAsOnThem) {
  ldraw::Model m = read_text(
      "0 t\n"
      "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 80 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 0 -25 0 1 0 0 0 1 0 0 0 1 3001.dat\n"       // 1 LDU above: on the brick below
      "1 4 80 -26 0 1 0 0 0 1 0 0 0 1 3001.dat\n"      // 2 LDU above: where it is
      "1 4 0 -49 0 0 1 0 -1 0 0 0 0 1 3001.dat\n"      // on its side: where it is
      "1 4 160 -23 0 1 0 0 0 -1 0 0 0 -1 3001.dat\n",  // upside down, 1 LDU below
      "t.ldr");
  parts::PartLibrary library({}, BrickCatalog::standard());
  auto conv = parts::to_assembly(m, library);
  ASSERT_EQ(conv.assembly.bricks.size(), 6u);
  EXPECT_EQ(conv.plates, 0);
  EXPECT_EQ(conv.assembly.bricks[2].pose->origin[1], -25) << "the builder places parts as drawn";
  take_onto_the_plates(conv);
  std::vector<double> heights;
  for (const auto& b : conv.assembly.bricks) heights.push_back(b.pose->origin[1]);
  EXPECT_EQ(heights, (std::vector<double>{0, 0, -24, -26, -49, -24}));
  ASSERT_EQ(conv.diagnostics.size(), 2u);
  EXPECT_EQ(conv.diagnostics[0].line, 4);
  EXPECT_NE(conv.diagnostics[0].message.find("placed 1 LDU above the plates"), std::string::npos)
      << conv.diagnostics[0].message;
  EXPECT_EQ(conv.diagnostics[1].line, 7);
  EXPECT_NE(conv.diagnostics[1].message.find("1 LDU below"), std::string::npos);
}

// A part whose studs meet nothing as drawn, 3 LDU beside the lattice of the rest, is moved onto
// it when that makes it meet what stands; one that would still float stays where it is drawn.
TEST(DrawnByEye, APartBesideTheLatticeIsMovedOnlyWhereThatMakesItStand) {
  ldraw::Model m = read_text(
      "0 t\n"
      "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 80 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 160 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 3 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"     // 3 LDU beside, on the first brick
      "1 4 163 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n",  // 3 LDU beside, over nothing
      "t.ldr");
  parts::PartLibrary library({}, BrickCatalog::standard());
  auto conv = parts::to_assembly(m, library);
  ASSERT_EQ(conv.assembly.bricks.size(), 5u);
  // What the contact graph would say, in short: a brick off the lattice meets no stud, and the
  // one two bricks up has nothing under it wherever it is.
  auto floating_now = [](const Assembly& a) {
    std::vector<char> out(a.bricks.size(), 0);
    for (size_t i = 3; i < a.bricks.size(); ++i)
      out[i] = i == 4 || std::abs(std::remainder(a.bricks[i].pose->origin[0], 20)) > 1e-9;
    return out;
  };
  EXPECT_TRUE(nudge_onto_the_lattice(conv, floating_now(conv.assembly), floating_now));
  EXPECT_EQ(conv.assembly.bricks[3].pose->origin[0], 0);
  EXPECT_EQ(conv.assembly.bricks[4].pose->origin[0], 163) << "moved back: it stands no better";
  ASSERT_EQ(conv.diagnostics.size(), 1u);
  EXPECT_EQ(conv.diagnostics[0].line, 5);
  EXPECT_NE(conv.diagnostics[0].message.find("3 LDU beside the lattice"), std::string::npos)
      << conv.diagnostics[0].message;
}

}  // namespace
}  // namespace lego::report
