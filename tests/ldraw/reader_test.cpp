#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "ldraw/reader.h"
#include "test_paths.h"

namespace lego::ldraw {
namespace {

namespace fs = std::filesystem;

int count(const Model& m, Severity s) {
  int n = 0;
  for (const auto& d : m.diagnostics) n += d.severity == s;
  return n;
}

const Diagnostic* find_diag(const Model& m, const std::string& needle) {
  for (const auto& d : m.diagnostics)
    if (d.message.find(needle) != std::string::npos) return &d;
  return nullptr;
}

TEST(Reader, ReadsHeaderPartsAndAllLineTypes) {
  Model m = read_text(
      "0 My model\n0 Name: my.ldr\n0 Author: A. Builder\n0 !LDRAW_ORG Unofficial_Model\n"
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "2 24 0 0 0 1 1 1\n3 16 0 0 0 1 0 0 0 0 1\n4 16 0 0 0 1 0 0 1 0 1 0 0 1\n"
      "5 24 0 0 0 1 0 0 0 0 1 1 1 1\n",
      "my.ldr");
  EXPECT_FALSE(m.has_errors());
  EXPECT_EQ(m.diagnostics.size(), 0u);
  EXPECT_EQ(m.title, "My model");
  EXPECT_EQ(m.name, "my.ldr");
  EXPECT_EQ(m.author, "A. Builder");
  EXPECT_EQ(m.ldraw_org, "Unofficial_Model");
  ASSERT_EQ(m.parts.size(), 1u);
  EXPECT_EQ(m.parts[0].part, "3001");
  EXPECT_EQ(m.parts[0].color, 4);
  EXPECT_EQ(m.parts[0].line, 5);
  EXPECT_DOUBLE_EQ(m.parts[0].transform.pos[1], -24);
}

TEST(Reader, MpdSubmodelsComposeTransformsAndInheritColour) {
  Model m = read_text(
      "0 FILE main.ldr\n0 Main\n"
      "1 4 100 0 0 0 0 1 0 1 0 -1 0 0 Sub Model.ldr\n"
      "0 STEP\n"
      "1 1 0 -24 0 1 0 0 0 1 0 0 0 1 3003.dat\n"
      "0 NOFILE\n"
      "0 FILE sub model.LDR\n0 Sub\n"
      "1 16 20 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 24 0 0 40 1 0 0 0 1 0 0 0 1 3005.dat\n"
      "0 NOFILE\n",
      "main.mpd");
  ASSERT_FALSE(m.has_errors()) << m.diagnostics.front().text();
  ASSERT_EQ(m.parts.size(), 3u);
  // Rotated 90 degrees about y: local x=20 lands at world z=-20, shifted by 100 in x.
  EXPECT_DOUBLE_EQ(m.parts[0].transform.pos[0], 100);
  EXPECT_DOUBLE_EQ(m.parts[0].transform.pos[2], -20);
  EXPECT_DOUBLE_EQ(m.parts[0].transform.rot[2], 1);
  EXPECT_EQ(m.parts[0].color, 4);                            // 16 inherits red
  EXPECT_EQ(m.parts[1].color, kDirectColorBase + 0x333333);  // 24: red's edge colour
  EXPECT_EQ(m.parts[0].submodel, "sub model.LDR");
  EXPECT_EQ(m.parts[0].step, 1);
  EXPECT_EQ(m.parts[2].step, 2);
  EXPECT_EQ(m.steps.size(), 2u);
  ASSERT_EQ(m.submodels.size(), 1u);
  EXPECT_EQ(m.main_block, "main.ldr");
}

// Each part keeps the submodel placements that hold it, exactly as written: their product with
// its own line is its world transform. A placement that holds no part is not kept.
TEST(Reader, PartsKeepTheSubmodelPlacementsThatHoldThem) {
  Model m = read_text(
      "0 FILE main.ldr\n"
      "1 16 5 0 0 0.866025 0 0.5 0 1 0 -0.5 0 0.866025 a.ldr\n"
      "1 16 0 0 0 1 0 0 0 1 0 0 0 1 empty.ldr\n"
      "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "0 FILE a.ldr\n1 16 0 -24 20 0 0 1 0 1 0 -1 0 0 b.ldr\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 "
      "empty.ldr\n"
      "0 FILE b.ldr\n1 1 10 -8 0 1 0 0 0 1 0 0 0 1 3020.dat\n"
      "0 FILE empty.ldr\n0 nothing here\n",
      "nested.mpd");
  ASSERT_EQ(m.parts.size(), 2u);
  EXPECT_EQ(m.placements.size(), 2u);  // a.ldr and b.ldr inside it; neither empty.ldr
  const PlacedPart& plate = m.parts[0];
  EXPECT_EQ(plate.part, "3020");
  ASSERT_GE(plate.inside, 0);
  std::vector<int> chain;
  for (int k = plate.inside; k >= 0; k = m.placements[size_t(k)].parent)
    chain.insert(chain.begin(), k);
  ASSERT_EQ(chain.size(), 2u);
  Transform world;
  for (int k : chain) world = world.then(m.placements[size_t(k)].transform);
  world = world.then(plate.local);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(world.pos[i], plate.transform.pos[i], 1e-9);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(world.rot[i], plate.transform.rot[i], 1e-9);
  EXPECT_EQ(plate.local.pos[0], 10);
  EXPECT_EQ(m.parts[1].inside, -1);  // the main model's own brick
}

TEST(Reader, RecordsStepsAndRotsteps) {
  Model m = read_text(
      "0 m\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 ROTSTEP 0 90 0 REL\n"
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 ROTSTEP END\n"
      "1 4 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
      "s.ldr");
  ASSERT_EQ(m.steps.size(), 3u);
  EXPECT_EQ(m.steps[0].rotstep, "0 90 0 REL");
  EXPECT_EQ(m.steps[1].rotstep, "END");
  EXPECT_EQ(m.steps[2].parts, 1);
  EXPECT_EQ(m.parts[2].step, 3);
}

// A leading ROTSTEP (a view turned before anything is placed) or two STEPs in a row make no
// step: step 1 is the first that places a part, as a builder counts them.
TEST(Reader, AStepThatPlacesNothingIsNoStep) {
  Model m = read_text(
      "0 m\n0 ROTSTEP 0 90 0 REL\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n0 STEP\n"
      "1 1 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
      "r.ldr");
  ASSERT_EQ(m.steps.size(), 2u);
  EXPECT_EQ(m.steps[0].number, 1);
  EXPECT_EQ(m.steps[1].number, 2);
  EXPECT_EQ(m.parts[0].step, 1);
  EXPECT_EQ(m.parts[1].step, 2);
}

// MLCad's buffers: a sub-assembly built aside (the model stored in A, the empty B shown, the
// sub-assembly built, A shown again), then put in place by GHOST lines. The finished model is
// what is shown at the end: the ghosts; the lines built aside are its parts list's.
TEST(Reader, ASubAssemblyBuiltAsideInABufferIsSetInPlaceByItsGhosts) {
  Model m = read_text(
      "0 m\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG A STORE\n0 BUFEXCHG B RETRIEVE\n"
      "1 2 70 -48 0 1 0 0 0 1 0 0 0 1 3005.dat\n0 STEP\n"
      "1 1 30 -72 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG a RETRIEVE\n"
      "0 GHOST 1 2 70 -48 0 1 0 0 0 1 0 0 0 1 3005.dat\n"
      "0 GHOST 1 1 30 -72 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG 7 STORE\n",
      "b.ldr");
  ASSERT_EQ(m.parts.size(), 3u);
  EXPECT_FALSE(m.parts[0].ghost);
  EXPECT_TRUE(m.parts[1].ghost);
  EXPECT_TRUE(m.parts[2].ghost);
  EXPECT_EQ(m.parts[1].step, 4);
  ASSERT_EQ(m.aside.size(), 2u);
  EXPECT_EQ(m.aside[0].part, "3005");
  EXPECT_EQ(m.aside[0].step, 2);
  EXPECT_EQ(m.aside[1].step, 3);
  ASSERT_EQ(m.steps.size(), 4u);
  const std::vector<std::pair<int, int>> counts{{1, 0}, {0, 1}, {0, 1}, {2, 0}};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(m.steps[k].number, int(k) + 1);
    EXPECT_EQ(m.steps[k].parts, counts[k].first) << k;
    EXPECT_EQ(m.steps[k].aside, counts[k].second) << k;
  }
  // The malformed exchange is named and ignored.
  bool named = false;
  for (const auto& d : m.diagnostics)
    named = named || (d.line == 14 && d.message.find("BUFEXCHG") != std::string::npos);
  EXPECT_TRUE(named);
  // Without buffers, a ghost is a part of the model all the same.
  const Model plain = read_text("0 g\n0 GHOST 1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n", "g.ldr");
  ASSERT_EQ(plain.parts.size(), 1u);
  EXPECT_TRUE(plain.parts[0].ghost);
  EXPECT_TRUE(plain.aside.empty());
}

// Each step that builds aside knows what its view shows of what is built aside: the sub-assembly
// so far. Two sub-assemblies in two buffers, the first taken up again after the second: each
// step's view shows its own, never the other's.
TEST(Reader, AStepBuildingAsideKnowsTheSubAssemblyItsViewShows) {
  const Model m = read_text(
      "0 m\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG A STORE\n0 BUFEXCHG B RETRIEVE\n"
      "1 1 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"  // aside 0, step 2
      "0 BUFEXCHG B STORE\n0 BUFEXCHG C RETRIEVE\n"
      "1 2 0 -24 0 1 0 0 0 1 0 0 0 1 3003.dat\n0 STEP\n"  // aside 1, step 3
      "0 BUFEXCHG B RETRIEVE\n"
      "1 1 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"  // aside 2, step 4
      "0 BUFEXCHG A RETRIEVE\n"
      "0 GHOST 1 1 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "0 GHOST 1 1 0 -72 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
      "two.ldr");
  ASSERT_EQ(m.aside.size(), 3u);
  ASSERT_EQ(m.steps.size(), 5u);
  EXPECT_TRUE(m.steps[0].aside_shown.empty());
  EXPECT_EQ(m.steps[1].aside_shown, (std::vector<int>{0}));
  EXPECT_EQ(m.steps[2].aside_shown, (std::vector<int>{1}));
  EXPECT_EQ(m.steps[3].aside_shown, (std::vector<int>{0, 2}));
  EXPECT_TRUE(m.steps[4].aside_shown.empty());
}

// A submodel with steps of its own is a sub-assembly built apart where it is first placed, as
// LPub3D's instructions build it: its steps, then the step that places it whole with the rest of
// that step's parts; its parts are in place from there. Placed again, it comes whole.
TEST(Reader, ASubmodelsOwnStepsBuildItApartBeforeTheStepThatPlacesIt) {
  Model m = read_text(
      "0 FILE main.ldr\n"
      "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"     // step 1
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 wall.ldr\n"           // the wall built apart: 2, 3
      "1 4 0 -96 0 1 0 0 0 1 0 0 0 1 3003.dat\n0 STEP\n"   // the step that places it: 4
      "1 4 80 -24 0 1 0 0 0 1 0 0 0 1 wall.ldr\n0 STEP\n"  // step 5: the wall whole
      "0 FILE wall.ldr\n"
      "1 16 0 0 0 1 0 0 0 1 0 0 0 1 3004.dat\n0 STEP\n"
      "1 16 0 -24 0 1 0 0 0 1 0 0 0 1 3004.dat\n0 STEP\n",
      "main.mpd");
  ASSERT_FALSE(m.has_errors());
  std::vector<int> steps, built_in;
  for (const auto& p : m.parts) {
    steps.push_back(p.step);
    built_in.push_back(p.built_in);
  }
  EXPECT_EQ(steps, (std::vector<int>{1, 4, 4, 4, 5, 5}));
  EXPECT_EQ(built_in, (std::vector<int>{0, 2, 3, 0, 0, 0}));
  ASSERT_EQ(m.steps.size(), 5u);
  const std::vector<std::pair<int, int>> counts{{1, 0}, {0, 1}, {0, 1}, {3, 0}, {2, 0}};
  for (size_t k = 0; k < counts.size(); ++k) {
    EXPECT_EQ(m.steps[k].parts, counts[k].first) << k;
    EXPECT_EQ(m.steps[k].aside, counts[k].second) << k;
  }
  // A part of the main model placed before the sub-assembly in the same step waits for it.
  Model before = read_text(
      "0 FILE main.ldr\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 wall.ldr\n0 STEP\n"
      "0 FILE wall.ldr\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 3004.dat\n0 STEP\n",
      "before.mpd");
  ASSERT_EQ(before.parts.size(), 2u);
  EXPECT_EQ(before.parts[0].step, 2);
  EXPECT_EQ(before.parts[1].step, 2);
  EXPECT_EQ(before.parts[1].built_in, 1);
  EXPECT_EQ(before.steps.size(), 2u);
}

// Real files are forgiving where LDraw tools are: an unknown colour code is a warning (LeoCAD
// draws the part), and old Mac files end lines with a bare CR that must not reach a name.
TEST(Reader, UnknownColoursAndBareCarriageReturns) {
  Model m = read_text(
      "0 m\n1 4294967295 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 blue 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n",
      "colours.ldr");
  EXPECT_FALSE(m.has_errors());
  ASSERT_EQ(m.parts.size(), 2u);
  EXPECT_EQ(m.parts[0].color, kMainColor);
  ASSERT_NE(find_diag(m, "unknown colour '4294967295'"), nullptr);
  EXPECT_EQ(find_diag(m, "unknown colour '4294967295'")->line, 2);
  Model mac = read_text(
      "0 Old Mac\r1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\r"
      "1 4 0 -48 0 1 0 0 0 1 0 0 0 1 3003.dat\r\n",
      "mac.ldr");
  ASSERT_EQ(mac.parts.size(), 2u);
  EXPECT_EQ(mac.title, "Old Mac");
  EXPECT_EQ(mac.parts[0].part, "3001");
  EXPECT_EQ(mac.parts[0].line, 2);
  EXPECT_EQ(mac.parts[1].part, "3003");
  EXPECT_EQ(mac.parts[1].line, 3);
}

TEST(Reader, MalformedTypeOneLineIsAnErrorWithItsLine) {
  Model m = read_text("0 m\n1 4 0 0 zero 1 0 0 0 1 0 0 0 1 3001.dat\n1 4 0 0 0 1 0 0 0 1 0 0 0 1\n",
                      "bad.ldr");
  EXPECT_EQ(count(m, Severity::Error), 2);
  EXPECT_EQ(m.diagnostics[0].line, 2);
  EXPECT_EQ(m.diagnostics[0].text(),
            "bad.ldr:2: error: malformed type-1 line: 'zero' is not a number");
  EXPECT_EQ(m.diagnostics[1].line, 3);
  EXPECT_TRUE(m.parts.empty());
}

TEST(Reader, SingularMatrixAbsurdCoordinatesAndShear) {
  Model m = read_text(
      "0 m\n1 4 0 0 0 0 0 0 0 1 0 0 0 1 3001.dat\n1 4 1e12 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 0 0 0 2 0 0 0 1 0 0 0 1 3001.dat\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n",
      "m.ldr");
  EXPECT_EQ(count(m, Severity::Error), 2);
  EXPECT_EQ(find_diag(m, "singular")->line, 2);
  EXPECT_EQ(find_diag(m, "absurd")->line, 3);
  ASSERT_EQ(m.parts.size(), 2u);  // the scaled part is read (tests/parts: it is carried)
  EXPECT_EQ(m.parts[0].line, 4);
}

TEST(Reader, MalformedMetaAndGeometryAreWarnings) {
  Model m =
      read_text("0 m\n0 ROTSTEP sideways\n3 16 0 0\n7 1 2 3\n0 !COLOUR Broken CODE x\n", "w.ldr");
  EXPECT_EQ(count(m, Severity::Error), 0);
  EXPECT_EQ(count(m, Severity::Warning), 4);
}

TEST(Reader, MissingSubmodelAndReferenceLoop) {
  Model m = read_text(
      "0 FILE a.ldr\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 b.ldr\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 nowhere.ldr\n"
      "0 FILE b.ldr\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 a.ldr\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n",
      "loop.mpd");
  const Diagnostic* loop = find_diag(m, "reference loop");
  ASSERT_NE(loop, nullptr);
  EXPECT_EQ(loop->line, 5);
  EXPECT_NE(loop->message.find("a.ldr -> b.ldr -> a.ldr"), std::string::npos);
  // A missing submodel is placed as a part with no file, for the assembly to leave out with its
  // line, as a missing part is.
  EXPECT_EQ(find_diag(m, "nowhere.ldr"), nullptr);
  ASSERT_EQ(m.parts.size(), 2u);
  EXPECT_EQ(m.parts[1].reference, "nowhere.ldr");
  EXPECT_EQ(m.parts[1].line, 3);
  EXPECT_TRUE(m.parts[1].definition.empty());
}

TEST(Reader, ExponentialNestingStopsAtTheBudget) {
  std::string text = "0 FILE m0.ldr\n";
  for (int level = 0; level < 30; ++level) {
    for (int k = 0; k < 10; ++k)
      text += "1 16 0 0 0 1 0 0 0 1 0 0 0 1 m" + std::to_string(level + 1) + ".ldr\n";
    text += "0 FILE m" + std::to_string(level + 1) + ".ldr\n";
  }
  text += "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n";
  ReadOptions options;
  options.max_parts = 1000;
  Model m = read_text(text, "bomb.mpd", options);
  EXPECT_EQ(m.parts.size(), 1000u);
  EXPECT_NE(find_diag(m, "more than 1000 parts"), nullptr);
}

// --max-seconds: reading stops where it is when the run's budget is spent, saying it was reading.
TEST(Reader, ReadingStopsWhenTheBudgetIsSpent) {
  const Budget spent(0);
  ReadOptions options;
  options.budget = &spent;
  try {
    read_text("1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n", "late.ldr", options);
    ADD_FAILURE() << "read past a spent budget";
  } catch (const OutOfTime& e) {
    EXPECT_EQ(e.stage(), "reading");
  }
  EXPECT_EQ(read_text("1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n", "late.ldr").parts.size(), 1u);
}

TEST(Reader, BinaryDirectoryAndMissingFiles) {
  Model binary = read_text(std::string("0 x\n\0\1\2", 7), "bin.ldr");
  ASSERT_TRUE(binary.has_errors());
  EXPECT_NE(binary.diagnostics[0].message.find("not a text file"), std::string::npos);
  Model dir = read_file(fs::temp_directory_path());
  ASSERT_TRUE(dir.has_errors());
  EXPECT_NE(dir.diagnostics[0].message.find("directory"), std::string::npos);
  Model missing = read_file("/nonexistent/model.ldr");
  ASSERT_TRUE(missing.has_errors());
  EXPECT_EQ(missing.diagnostics[0].file, "/nonexistent/model.ldr");
}

TEST(Reader, CrlfBomAndNoFinalNewline) {
  Model m = read_text(
      "\xEF\xBB\xBF"
      "0 T\r\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.DAT",
      "c.ldr");
  EXPECT_FALSE(m.has_errors());
  ASSERT_EQ(m.parts.size(), 1u);
  EXPECT_EQ(m.parts[0].part, "3001");
  EXPECT_EQ(m.title, "T");
}

// Multi-file models: parts and submodels that are files next to the model, and an LDraw library.
TEST(Reader, ResolvesLocalFilesAndLibrary) {
  auto dir = fs::temp_directory_path() / "lego_reader_multi";
  fs::remove_all(dir);
  fs::create_directories(dir / "lib" / "parts");
  std::ofstream(dir / "Wing.LDR") << "0 Wing\n1 16 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n";
  std::ofstream(dir / "custom.dat")
      << "0 Custom\n0 !LDRAW_ORG Unofficial_Part\n4 16 0 0 0 1 0 0 1 0 1 0 0 1\n";
  std::ofstream(dir / "lib" / "parts" / "3068b.dat")
      << "0 Tile\n0 !LDRAW_ORG Part UPDATE 2004-03\n";
  std::ofstream(dir / "main.ldr") << "0 Main\n1 2 0 0 0 1 0 0 0 1 0 0 0 1 wing.ldr\n"
                                     "1 1 0 0 0 1 0 0 0 1 0 0 0 1 custom.dat\n"
                                     "1 1 0 0 0 1 0 0 0 1 0 0 0 1 3068b.dat\n";
  ReadOptions options;
  options.library_dirs = {dir / "lib"};
  Model m = read_file(dir / "main.ldr", options);
  ASSERT_FALSE(m.has_errors());
  ASSERT_EQ(m.parts.size(), 3u);
  EXPECT_EQ(m.parts[0].part, "3001");
  EXPECT_EQ(m.parts[0].color, 2);
  EXPECT_EQ(m.parts[0].file, (dir / "Wing.LDR").string());
  EXPECT_EQ(m.parts[1].definition, dir / "custom.dat");
  EXPECT_EQ(m.parts[2].definition, dir / "lib" / "parts" / "3068b.dat");
  fs::remove_all(dir);
}

// Files nest up to 64 levels, the main model's included (ReadOptions::max_depth): 63 submodels
// one inside the next. One more is an error at the line of the reference that goes deeper.
TEST(Reader, SubmodelsNestAtMost64Deep) {
  auto nested = [](int levels) {
    std::string text;
    for (int i = 0; i < levels; ++i)
      text += "0 FILE s" + std::to_string(i) + ".ldr\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 s" +
              std::to_string(i + 1) + ".ldr\n";
    return text + "0 FILE s" + std::to_string(levels) +
           ".ldr\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n";
  };
  Model ok = read_text(nested(63), "ok.mpd");
  EXPECT_FALSE(ok.has_errors());
  EXPECT_EQ(ok.parts.size(), 1u);
  Model deep = read_text(nested(64), "deep.mpd");
  ASSERT_TRUE(deep.has_errors());
  const Diagnostic* d = find_diag(deep, "nested deeper than 64 levels");
  ASSERT_NE(d, nullptr);
  EXPECT_GT(d->line, 0);
  EXPECT_TRUE(deep.parts.empty());
}

// Datsville's figures and patterned slopes embed unofficial parts without an !LDRAW_ORG line:
// a block drawn only from primitives and subparts is a part, not a submodel whose primitives
// would be placed as parts of the model. A block that places a part stays a submodel.
TEST(Reader, EmbeddedBlocksDrawnFromPrimitivesAreParts) {
  auto dir = fs::temp_directory_path() / "lego_reader_embedded";
  fs::remove_all(dir);
  fs::create_directories(dir / "lib" / "p");
  fs::create_directories(dir / "lib" / "parts" / "s");
  std::ofstream(dir / "lib" / "p" / "4-4disc.dat") << "0 Disc\n0 !LDRAW_ORG Primitive\n";
  std::ofstream(dir / "lib" / "parts" / "s" / "973s01.dat") << "0 ~Torso\n";
  std::ofstream(dir / "figure.mpd")
      << "0 FILE figure.ldr\n0 Figure\n1 16 0 -72 0 1 0 0 0 1 0 0 0 1 973t03.dat\n"
         "1 14 0 -96 0 1 0 0 0 1 0 0 0 1 badge.dat\n"
         "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 stand.dat\n0 NOFILE\n"
         "0 FILE 973t03.dat\n0 Torso with a print\n"
         "1 16 0 0 0 1 0 0 0 1 0 0 0 1 s\\973s01.dat\n"
         "1 14 0 19 -10 1 0 0 0 0 -1 0 1 0 4-4disc.dat\n0 NOFILE\n"
         "0 FILE badge.dat\n3 16 0 0 0 1 0 0 0 0 1\n0 NOFILE\n"
         "0 FILE stand.dat\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
         "1 16 0 0 0 1 0 0 0 1 0 0 0 1 4-4disc.dat\n0 NOFILE\n";
  std::ofstream(dir / "main.ldr") << "0 Main\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 figure.mpd\n";
  ReadOptions options;
  options.library_dirs = {dir / "lib"};
  Model m = read_file(dir / "main.ldr", options);
  ASSERT_FALSE(m.has_errors());
  std::vector<std::string> names;
  for (const auto& p : m.parts) names.push_back(p.part);
  EXPECT_EQ(names, (std::vector<std::string>{"973t03", "badge", "3001", "4-4disc"}));
  EXPECT_EQ(m.parts[0].embedded_definition, "973t03.dat");
  std::set<std::string> embedded;
  for (const auto& [name, text] : m.embedded_parts) embedded.insert(name);
  EXPECT_EQ(embedded, (std::set<std::string>{"973t03.dat", "badge.dat"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lego::ldraw
