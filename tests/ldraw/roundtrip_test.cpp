#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "ldraw/assembly_builder.h"
#include "ldraw/reader.h"
#include "ldraw/writer.h"

namespace lego::ldraw {
namespace {

bool same_bricks(const Assembly& a, const Assembly& b) {
  if (a.bricks.size() != b.bricks.size()) return false;
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    const Brick &x = a.bricks[i], &y = b.bricks[i];
    if (x.type != y.type || !(x.min == y.min) || x.rotated != y.rotated || x.color != y.color)
      return false;
  }
  return true;
}

Assembly random_assembly(unsigned seed) {
  const auto& catalog = BrickCatalog::standard();
  std::mt19937 rng(seed);
  Assembly a;
  a.origin_ldu = {10, 0, 0};
  for (int i = 0; i < 40; ++i) {
    Brick b;
    b.type = &catalog.types()[rng() % catalog.types().size()];
    b.min = {int(rng() % 20) - 10, int(rng() % 30), int(rng() % 20) - 10};
    b.rotated = rng() % 2;
    b.color = std::array{1, 4, 14, 15, 0x2123456}[rng() % 5];
    b.source.step = 1 + i / 10;
    a.bricks.push_back(b);
  }
  return a;
}

TEST(RoundTrip, LdrAndMpdGiveBackTheSameBricks) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Assembly a = random_assembly(seed);
    for (bool mpd : {false, true}) {
      WriteOptions options;
      options.title = "Round trip";
      std::string text = mpd ? to_mpd(a, options) : to_ldr(a, options);
      Model m = read_text(text, mpd ? "rt.mpd" : "rt.ldr");
      ASSERT_FALSE(m.has_errors());
      EXPECT_EQ(m.title, "Round trip");
      EXPECT_EQ(m.steps.size(), 4u);
      auto back = to_assembly(m, BrickCatalog::standard());
      EXPECT_TRUE(back.skipped.empty());
      EXPECT_EQ(back.assembly.origin_ldu, a.origin_ldu);
      EXPECT_TRUE(same_bricks(a, back.assembly)) << "seed " << seed << " mpd " << mpd;
      for (const Brick& b : back.assembly.bricks) EXPECT_GE(b.source.step, 1);
    }
  }
}

TEST(RoundTrip, WriterHeaderAndAtomicWrite) {
  Assembly a = random_assembly(7);
  auto path = std::filesystem::temp_directory_path() / "lego_rt.ldr";
  write_model(path, a, {.title = "T", .name = "", .author = "Me", .steps = true});
  Model m = read_file(path);
  EXPECT_EQ(m.name, "lego_rt.ldr");
  EXPECT_EQ(m.author, "Me");
  EXPECT_EQ(m.ldraw_org, "Unofficial_Model");
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp-legolization"));
  EXPECT_THROW(write_model("/nonexistent-dir/x.ldr", a, {}), std::runtime_error);
}

TEST(ToAssembly, LatticeOrientationAndUnknownParts) {
  Model m = read_text(
      "0 t\n"
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"    // 2x4 at origin, bottom at y=0
      "1 4 0 -48 0 0 0 1 0 1 0 -1 0 0 3001.dat\n"   // turned 90 degrees
      "1 4 0 -72 0 -1 0 0 0 1 0 0 0 -1 3001.dat\n"  // 180 degrees
      "1 4 5 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"    // 5 LDU off
      "1 4 0 -24 0 1 0 0 0 -1 0 0 0 -1 3001.dat\n"  // upside down
      "1 4 0 -24 0 0.7071 0 0.7071 0 1 0 -0.7071 0 0.7071 3001.dat\n"  // 45 degrees
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3068b.dat\n",                     // not in the catalog
      "t.ldr");
  auto conv = to_assembly(m, BrickCatalog::standard());
  ASSERT_EQ(conv.assembly.bricks.size(), 3u);
  const auto& b = conv.assembly.bricks;
  EXPECT_EQ(b[0].min, (LatticePoint{-2, 0, -1}));
  EXPECT_FALSE(b[0].rotated);
  EXPECT_TRUE(b[1].rotated);
  EXPECT_EQ(b[1].min, (LatticePoint{-1, 3, -2}));
  EXPECT_EQ(b[2].min.y, 6);
  EXPECT_FALSE(b[2].rotated);
  ASSERT_EQ(conv.skipped.size(), 4u);
  EXPECT_NE(conv.skipped[0].reason.find("off the lattice"), std::string::npos);
  EXPECT_EQ(m.parts[conv.skipped[0].part].line, 5);
  EXPECT_NE(conv.skipped[1].reason.find("upside down"), std::string::npos);
  EXPECT_NE(conv.skipped[2].reason.find("not a multiple of 90"), std::string::npos);
  EXPECT_NE(conv.skipped[3].reason.find("unknown part"), std::string::npos);
}

}  // namespace
}  // namespace lego::ldraw
