#include <gtest/gtest.h>

#include <fstream>

#include "core/brick_catalog.h"
#include "core/error.h"
#include "ldraw/reader.h"

namespace lego {
namespace {

TEST(Catalog, ListsEveryStandardBrickAndPlateWithPaperMasses) {
  const auto& catalog = BrickCatalog::standard();
  for (const char* part :
       {"3005", "3004", "3622", "3010", "3009", "3008", "3003", "3002", "3001", "2456", "3007",
        "3024", "3023", "3623", "3710", "3666", "3460", "3022", "3021", "3020", "3795", "3034"})
    EXPECT_NE(catalog.find(part), nullptr) << part;
  const BrickType* b = catalog.find("3001.DAT");
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->length, 4);
  EXPECT_EQ(b->width, 2);
  EXPECT_EQ(b->height, 3);
  EXPECT_DOUBLE_EQ(b->mass_g, 2.20);
  EXPECT_DOUBLE_EQ(catalog.find("3008")->mass_g, 3.08);
  EXPECT_EQ(catalog.find_by_size(1, 8, 3), catalog.find("3008"));
  EXPECT_EQ(catalog.find_by_size(2, 4, 1), catalog.find("3020"));
  EXPECT_EQ(catalog.find("3068b"), nullptr);
}

TEST(Catalog, RejectsMalformedCatalogWithLine) {
  auto path = std::filesystem::temp_directory_path() / "lego_bad_catalog.csv";
  std::ofstream(path)
      << "part,name,kind,length,width,height,mass_g,mass_source\n3001,x,brick,four,2,3,1,src\n";
  try {
    BrickCatalog::load(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
  }
}

// Every part file we draw must match the catalog: box of the right LDU size, one stud per knob.
TEST(Catalog, PartFilesMatchTheCatalog) {
  const auto& catalog = BrickCatalog::standard();
  for (const auto& type : catalog.types()) {
    auto path = default_parts_dir() / "parts" / (type.part + ".dat");
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    std::string line;
    double min[3] = {1e9, 1e9, 1e9}, max[3] = {-1e9, -1e9, -1e9};
    int studs = 0;
    bool certified = false;
    while (std::getline(in, line)) {
      if (line.find("BFC CERTIFY CCW") != std::string::npos) certified = true;
      std::istringstream s(line);
      int kind = -1, color;
      s >> kind >> color;
      if (kind == 1) {
        ++studs;
        continue;
      }
      if (kind != 4) continue;
      for (int v = 0; v < 4; ++v)
        for (int a = 0; a < 3; ++a) {
          double c;
          s >> c;
          min[a] = std::min(min[a], c);
          max[a] = std::max(max[a], c);
        }
    }
    EXPECT_TRUE(certified) << type.part;
    EXPECT_EQ(studs, type.length * type.width) << type.part;
    EXPECT_DOUBLE_EQ(max[0] - min[0], 20.0 * type.length) << type.part;
    EXPECT_DOUBLE_EQ(max[2] - min[2], 20.0 * type.width) << type.part;
    EXPECT_DOUBLE_EQ(min[1], 0.0) << type.part;  // origin at the top of the body
    EXPECT_DOUBLE_EQ(max[1], 8.0 * type.height) << type.part;
  }
}

TEST(Catalog, ColorTableHasTheColoursBuildersUse) {
  const auto& colors = ldraw::ColorTable::standard();
  for (int code : {0,  1,  2,  4,  5,  6,  7,  8,   10,  11,  13,  14,  15,  19,  22,  25, 26,
                   27, 28, 70, 71, 72, 73, 85, 191, 226, 272, 288, 308, 320, 378, 379, 484})
    EXPECT_NE(colors.find(code), nullptr) << code;
  EXPECT_EQ(colors.name(4), "Red");
  EXPECT_EQ(*colors.rgb(0x2FF0000), 0xFF0000u);
  EXPECT_EQ(colors.name(9999), "colour 9999");
}

}  // namespace
}  // namespace lego
