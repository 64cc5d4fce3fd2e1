// The real models in ../shared/ldraw-models read without errors, with their parts, submodels
// and steps accounted for. A submodel's own steps build it apart where it is first placed, as
// LPub3D shows them, before the step that places it whole; a STEP that places nothing (after a
// submodel's own last STEP, or two in a row) makes no step.
#include <gtest/gtest.h>

#include "ldraw/reader.h"
#include "parts/assembly_builder.h"
#include "test_paths.h"

namespace lego::ldraw {
namespace {

struct Expected {
  const char* file;
  size_t parts;
  size_t submodels;
  size_t steps;
  const char* main_block;
};

void PrintTo(const Expected& e, std::ostream* os) {
  *os << e.file;
}

class SharedModels : public testing::TestWithParam<Expected> {};

TEST_P(SharedModels, ReadWithoutErrors) {
  SKIP_WITHOUT_SHARED();
  const Expected& e = GetParam();
  Model m = read_file(test::shared_dir() / "ldraw-models" / e.file);
  for (const auto& d : m.diagnostics) EXPECT_NE(d.severity, Severity::Error) << d.text();
  EXPECT_EQ(m.parts.size(), e.parts);
  EXPECT_EQ(m.submodels.size(), e.submodels);
  EXPECT_EQ(m.steps.size(), e.steps);
  EXPECT_EQ(m.main_block, e.main_block);
  int step_parts = 0, step_apart = 0, built_apart = 0;
  for (const auto& s : m.steps) {
    EXPECT_GT(s.parts + s.aside, 0)
        << "step " << s.number << ": a step that places nothing is no step";
    step_parts += s.parts;
    step_apart += s.aside;
  }
  for (const auto& p : m.parts) {
    built_apart += p.built_in > 0;
    if (p.built_in > 0) {
      EXPECT_LT(p.built_in, p.step) << "built apart before it is placed";
    }
  }
  EXPECT_EQ(size_t(step_parts), m.parts.size());
  EXPECT_EQ(step_apart, built_apart + int(m.aside.size()));
}

// Counts checked against ../shared/ldraw-models/README.md (type-1 lines, submodel references,
// one submodel used twice) and by reading each file.
INSTANTIATE_TEST_SUITE_P(
    Real, SharedModels,
    testing::Values(Expected{"car.ldr", 61, 0, 8, "car.ldr"},
                    Expected{"30023-1-Lighthouse.ldr", 25, 0, 1, "30023-1-Lighthouse.ldr"},
                    Expected{"889-1-RadarTruck.mpd", 35, 3, 7, "889 - Rader Truck.ldr"},
                    Expected{"4838-1-MiniVehicles.mpd", 79, 2, 27,
                             "4838 - Mini Vehicles - Carrier and Car.mpd"},
                    // "Side" is placed twice: 62 part lines + 5 more parts.
                    Expected{"4915-1-MiniConstruction.mpd", 67, 5, 38,
                             "4915 - Mini Construction - Excavator.mpd"},
                    Expected{"5935-1-IslandHopper.mpd", 203, 4, 1, "5935 - Island Hopper.ldr"},
                    Expected{"1621-1-LunarMPVVehicle.mpd", 104, 12, 1,
                             "1621 - Lunar MPV Vehicle.ldr"},
                    // The first FILE is the left door: the spec's main model, with a warning.
                    Expected{"Bulldog.mpd", 9, 0, 5, "LDoor.dat"},
                    Expected{"car.ldr_Packed.mpd", 61, 0, 8, "car.ldr_Packed.mpd"}),
    [](const auto& info) {
      std::string n = info.param.file;
      for (char& c : n)
        if (!isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

}  // namespace
}  // namespace lego::ldraw

namespace lego::ldraw {
namespace {

TEST(SharedModelsDetail, BulldogWarnsAboutItsMainModelAndCanBeReadWhole) {
  SKIP_WITHOUT_SHARED();
  auto path = test::shared_dir() / "ldraw-models" / "Bulldog.mpd";
  Model m = read_file(path);
  ASSERT_FALSE(m.diagnostics.empty());
  EXPECT_NE(m.diagnostics[0].message.find("'Bulldog.dat' is used by nothing"), std::string::npos);
  ReadOptions options;
  options.main_model = "bulldog.dat";
  Model whole = read_file(path, options);
  EXPECT_FALSE(whole.has_errors());
  EXPECT_EQ(whole.parts.size(), 123u);  // 105 part lines + two doors of 9 parts
  EXPECT_EQ(whole.submodels.size(), 2u);
}

// Colours our table lacks (the transparent ones) are named by the library's LDConfig.ldr.
TEST(SharedModelsDetail, TheLibrarysColourTableNamesWhatOursLacks) {
  SKIP_WITHOUT_SHARED();
  const auto car = test::shared_dir() / "ldraw-models" / "car.ldr";
  EXPECT_EQ(read_file(car).color_table.name(36), "colour 36");
  ReadOptions options;
  options.library_dirs = {test::shared_dir() / "ldraw-library"};
  const Model m = read_file(car, options);
  EXPECT_EQ(m.color_table.name(36), "Trans_Red");
  EXPECT_EQ(m.color_table.name(4), "Red");  // ours, as before
  EXPECT_EQ(m.color_table.rgb(36), 0xC91A09u);
}

TEST(SharedModelsDetail, PackedMpdResolvesEmbeddedParts) {
  SKIP_WITHOUT_SHARED();
  Model m = read_file(test::shared_dir() / "ldraw-models" / "car.ldr_Packed.mpd");
  EXPECT_EQ(m.diagnostics.size(), 0u);
  for (const auto& p : m.parts) EXPECT_FALSE(p.embedded_definition.empty()) << p.reference;
  EXPECT_EQ(m.parts[0].part, "4315");
  EXPECT_GE(m.embedded_parts.size(), 100u);
  parts::PartLibrary library({}, BrickCatalog::standard());
  auto conv = parts::to_assembly(m, library);
  auto plain =
      parts::to_assembly(read_file(test::shared_dir() / "ldraw-models" / "car.ldr"), library);
  // The packed file carries its parts: every one is known, and most are analysed as structure;
  // without a library, the plain file's parts outside the catalog are left out.
  EXPECT_TRUE(conv.skipped.empty());
  EXPECT_NE(conv.types->find("3031"), nullptr);
  EXPECT_NE(conv.types->find("3068b"), nullptr);
  EXPECT_GT(conv.assembly.bricks.size(), plain.assembly.bricks.size());
  EXPECT_EQ(plain.assembly.bricks.size() + plain.assembly.carried.size() + plain.skipped.size(),
            m.parts.size());
}

}  // namespace
}  // namespace lego::ldraw
