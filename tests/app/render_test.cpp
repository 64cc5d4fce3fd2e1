// Real client: LeoCAD renders our output with our own part library (DESIGN.md, "Real clients").
// Skips when leocad or xvfb-run is not installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "app/run_tool.h"
#include "core/brick_catalog.h"
#include "ldraw/reader.h"
#include "mesh/image.h"
#include "test_paths.h"

namespace lego {
namespace {

namespace fs = std::filesystem;

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

// Renders `model` with the part library `library`; empty image when LeoCAD fails.
Image render(const fs::path& library, const fs::path& model, const fs::path& png) {
  fs::remove(png);
  std::string cmd = "xvfb-run -a leocad -l " + test::quote(library.string()) + " -i " +
                    test::quote(png.string()) + " -w 400 -h 300 " + test::quote(model.string()) +
                    " >/dev/null 2>&1";
  Image image;
  if (std::system(cmd.c_str()) != 0 || !fs::exists(png)) return image;
  mesh::Texture decoded;
  std::string why;
  if (!mesh::load_image(png, decoded, why)) return image;
  image.width = decoded.width;
  image.height = decoded.height;
  image.rgb = std::move(decoded.rgb);
  return image;
}

// Parts referenced by a model that our library does not have would be drawn as boxes.
void expect_parts_exist(const fs::path& model) {
  for (const auto& p : ldraw::read_file(model).parts)
    EXPECT_TRUE(fs::exists(default_parts_dir() / "parts" / (p.part + ".dat"))) << p.reference;
}

size_t differing_pixels(const Image& a, const Image& b) {
  size_t n = 0;
  for (size_t i = 0; i + 2 < a.rgb.size() && i + 2 < b.rgb.size(); i += 3)
    n += std::abs(a.rgb[i] - b.rgb[i]) + std::abs(a.rgb[i + 1] - b.rgb[i + 1]) +
             std::abs(a.rgb[i + 2] - b.rgb[i + 2]) >
         30;
  return n;
}

size_t non_background_pixels(const Image& a) {
  size_t n = 0;
  for (size_t i = 0; i + 2 < a.rgb.size(); i += 3)
    n += a.rgb[i] + a.rgb[i + 1] + a.rgb[i + 2] < 3 * 245;
  return n;
}

// LeoCAD renders `model` with our parts, all of which exist, into a picture with some content.
void expect_renders(const fs::path& model, const fs::path& png, size_t min_pixels) {
  expect_parts_exist(model);
  Image image = render(default_parts_dir(), model, png);
  ASSERT_GT(image.width, 0) << "LeoCAD did not render " << model;
  EXPECT_GT(non_background_pixels(image), min_pixels);
}

class LeoCad : public testing::Test {
 protected:
  void SetUp() override {
    if (!test::have("leocad") || !test::have("xvfb-run"))
      GTEST_SKIP() << "leocad or xvfb-run is not installed";
    dir_ = test::scratch("lego_render_", "");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  fs::path dir_;
};

TEST_F(LeoCad, RendersOurPartsWithKnobs) {
  // One of each catalog part, side by side.
  auto model = dir_ / "catalog.ldr";
  {
    std::ofstream out(model);
    out << "0 Every part we ship\n";
    int x = 0;
    for (const auto& t : BrickCatalog::standard().types()) {
      out << "1 " << (t.kind == "plate" ? 1 : 4) << " " << x << " " << -8 * t.height
          << " 0 1 0 0 0 1 0 0 0 1 " << t.part << ".dat\n";
      x += 20 * t.length + 20;
    }
  }
  expect_parts_exist(model);
  Image with_knobs = render(default_parts_dir(), model, dir_ / "with.png");
  ASSERT_GT(with_knobs.width, 0) << "LeoCAD did not render";
  EXPECT_GT(non_background_pixels(with_knobs), 2000u);
  // The same library with the stud primitive emptied: the knobs must be what changes.
  auto bare = dir_ / "bare-library";
  fs::copy(default_parts_dir(), bare, fs::copy_options::recursive);
  std::ofstream(bare / "p" / "stud.dat", std::ios::trunc) << "0 Stud (empty)\n0 Name: stud.dat\n";
  Image without_knobs = render(bare, model, dir_ / "without.png");
  ASSERT_GT(without_knobs.width, 0);
  EXPECT_GT(differing_pixels(with_knobs, without_knobs), 500u);
}

TEST_F(LeoCad, OpensTheHeatMap) {
  auto heat = dir_ / "heat.ldr";
  auto run =
      test::run_tool("brickcheck", {"--quiet", "--heatmap", heat.string(),
                                    (test::data_dir() / "bridges" / "bridge-a-04.ldr").string()});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  expect_renders(heat, dir_ / "heat.png", 1000);
}

TEST_F(LeoCad, RendersTheLegolizedBunny) {
  SKIP_WITHOUT_SHARED();
  auto model = dir_ / "bunny.mpd";
  auto run = test::run_tool(
      "legolize", {(test::shared_dir() / "meshes" / "bunny.obj").string(), "--height", "40",
                   "--no-step-analysis", "--quiet", "-o", model.string()});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  expect_renders(model, dir_ / "bunny.png", 5000);
}

TEST_F(LeoCad, RendersALegolizedSampleHeatMap) {
  auto heat = dir_ / "crate-heat.ldr";
  auto run = test::run_tool(
      "legolize",
      {(test::data_dir() / ".." / ".." / "samples" / "crate.obj").string(), "--height", "6",
       "--quiet", "-o", (dir_ / "crate.ldr").string(), "--heatmap", heat.string()});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  expect_renders(heat, dir_ / "crate-heat.png", 1000);
}

}  // namespace
}  // namespace lego
