#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

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

// Supports (Brick::support) are the step-1 submodel "<name>-supports.ldr" of an .mpd, and a
// LeoCAD group of their own in an .ldr, with words that say what they are; read back, the same
// bricks in the same steps.
TEST(RoundTrip, SupportsAreASubmodelOrAGroupOfTheirOwn) {
  Assembly a = random_assembly(4);
  for (size_t i = 0; i < 10; ++i) a.bricks[i].support = true;  // step 1
  for (bool mpd : {false, true}) {
    WriteOptions options;
    options.name = mpd ? "rt.mpd" : "rt.ldr";
    const std::string text = mpd ? to_mpd(a, options) : to_ldr(a, options);
    EXPECT_NE(text.find("0 // Supports: columns that are not the model's"), std::string::npos);
    if (mpd) {
      EXPECT_NE(text.find("1 16 0 0 0 1 0 0 0 1 0 0 0 1 rt-supports.ldr\n0 STEP\n"),
                std::string::npos);
      EXPECT_NE(text.find("0 FILE rt-supports.ldr\n"), std::string::npos);
      EXPECT_NE(text.find("rt-step-002.ldr"), std::string::npos) << "steps keep their numbers";
    } else {
      const size_t begin = text.find("0 !LEOCAD GROUP BEGIN Supports\n");
      const size_t end = text.find("0 !LEOCAD GROUP END\n");
      ASSERT_NE(begin, std::string::npos);
      ASSERT_NE(end, std::string::npos);
      const std::string group = text.substr(begin, end - begin);
      EXPECT_EQ(std::count(group.begin(), group.end(), '\n'), 11) << group;  // 10 bricks
      EXPECT_EQ(group.find("STEP"), std::string::npos);
    }
    Model m = read_text(text, options.name);
    ASSERT_FALSE(m.has_errors());
    EXPECT_EQ(m.steps.size(), 4u);
    parts::PartLibrary library({}, BrickCatalog::standard());
    EXPECT_TRUE(same_bricks(a, parts::to_assembly(m, library).assembly));
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
  for (const auto& e : std::filesystem::directory_iterator(path.parent_path()))
    EXPECT_FALSE(e.path().filename().string().starts_with("lego_rt.ldr.tmp")) << e.path();
  EXPECT_THROW(write_model("/nonexistent-dir/x.ldr", a, {}), std::runtime_error);
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("lego_writer_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// An output's temporary is a new file with a name no one can guess (mkstemp): a link planted
// under the name it once had ("OUT.tmp-legolization") is not written through, and the file it
// points to stays as it was.
TEST(Writer, APlantedLinkIsNeverWrittenThrough) {
  const auto dir = fresh_dir("link");
  const auto victim = dir / "precious.txt", out = dir / "out.ldr";
  std::ofstream(victim) << "precious\n";
  std::filesystem::create_symlink(victim, dir / "out.ldr.tmp-legolization");
  write_file_atomically(out, "0 new\n");
  EXPECT_EQ(contents(victim), "precious\n");
  EXPECT_EQ(contents(out), "0 new\n");
  EXPECT_FALSE(std::filesystem::is_symlink(out));
  size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) ++entries, (void)e;
  EXPECT_EQ(entries, 3u) << "a temporary left behind";
}

// Two runs writing one output at once each put a whole file in place: they once shared one
// temporary, truncated each other's text and failed to rename.
TEST(Writer, RunsWritingOneFileAtOnceNeverMix) {
  const auto dir = fresh_dir("race");
  const auto out = dir / "out.ldr";
  const std::string a(300000, 'a'), b(200000, 'b');
  std::atomic<int> failures{0};
  auto write_often = [&](const std::string& text) {
    for (int k = 0; k < 100; ++k) try {
        write_file_atomically(out, text);
      } catch (const std::exception&) {
        ++failures;
      }
  };
  std::thread first(write_often, a), second(write_often, b);
  first.join();
  second.join();
  EXPECT_EQ(failures, 0);
  const std::string written = contents(out);
  EXPECT_TRUE(written == a || written == b) << written.size() << " bytes";
  size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) ++entries, (void)e;
  EXPECT_EQ(entries, 1u) << "a temporary left behind";
}

// A new output gets the mode any new file gets here (the umask's); one it replaces keeps its own.
TEST(Writer, OutputsKeepTheModeTheyHadOrGetTheUsualOne) {
  namespace fs = std::filesystem;
  const auto dir = fresh_dir("mode");
  std::ofstream(dir / "usual.txt") << "x";
  write_file_atomically(dir / "new.ldr", "0 new\n");
  EXPECT_EQ(fs::status(dir / "new.ldr").permissions(), fs::status(dir / "usual.txt").permissions());
  std::ofstream(dir / "kept.ldr") << "0 old\n";
  fs::permissions(dir / "kept.ldr",
                  fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write_file_atomically(dir / "kept.ldr", "0 new\n");
  EXPECT_EQ(fs::status(dir / "kept.ldr").permissions(),
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(contents(dir / "kept.ldr"), "0 new\n");
}

}  // namespace
}  // namespace lego::ldraw
