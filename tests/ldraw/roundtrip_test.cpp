#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "ldraw/reader.h"
#include "ldraw/writer.h"
#include "parts/assembly_builder.h"

namespace lego::ldraw {
namespace {

// The same parts in the same places: read back, a brick has its LDraw pose.
bool same_bricks(const Assembly& a, const Assembly& b) {
  if (a.bricks.size() != b.bricks.size()) return false;
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    const Brick &x = a.bricks[i], &y = b.bricks[i];
    const Transform tx = brick_transform(x, a.origin_ldu), ty = brick_transform(y, b.origin_ldu);
    if (x.type->part != y.type->part || tx.pos != ty.pos || tx.rot != ty.rot || x.color != y.color)
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
      parts::PartLibrary library({}, BrickCatalog::standard());
      auto back = parts::to_assembly(m, library);
      EXPECT_TRUE(back.skipped.empty());
      EXPECT_TRUE(back.assembly.carried.empty());
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

}  // namespace
}  // namespace lego::ldraw
