#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "app/run_tool.h"
#include "ldraw/reader.h"
#include "test_paths.h"

namespace lego {
namespace {

namespace fs = std::filesystem;
using test::run_tool;

fs::path scratch(const std::string& name) {
  return test::scratch("lego_legolize_", name);
}

// A 12-unit cube whose faces are red (-x), green (+x), blue (-y), yellow (+y), cyan (-z),
// magenta (+z) as OBJ + MTL.
fs::path coloured_cube() {
  auto obj = scratch("cube.obj");
  std::ofstream(scratch("cube.mtl"))
      << "newmtl mx\nKd 1 0 0\nnewmtl px\nKd 0 1 0\nnewmtl my\nKd 0 0 1\n"
         "newmtl py\nKd 1 1 0\nnewmtl mz\nKd 0 1 1\nnewmtl pz\nKd 1 0 1\n";
  std::ofstream out(obj);
  out << "mtllib cube.mtl\n";
  for (int i = 0; i < 8; ++i)
    out << "v " << 12 * (i & 1) << " " << 12 * ((i >> 1) & 1) << " " << 12 * ((i >> 2) & 1) << "\n";
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  const char* names[6] = {"mx", "px", "my", "py", "mz", "pz"};
  for (int k = 0; k < 6; ++k)
    out << "usemtl " << names[k] << "\nf " << faces[k][0] + 1 << " " << faces[k][1] + 1 << " "
        << faces[k][2] + 1 << " " << faces[k][3] + 1 << "\n";
  return obj;
}

TEST(Legolize, VoxelsOnlyWritesOneBrickPerVoxelInPaletteColours) {
  auto out = scratch("cube.ldr");
  auto run = run_tool("legolize", {coloured_cube().string(), "--voxels-only", "--height", "10",
                                   "--palette", "all", "-o", out.string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ldraw::Model m = ldraw::read_file(out);
  ASSERT_FALSE(m.has_errors());
  EXPECT_EQ(m.steps.size(), 10u);  // a layer per step
  std::map<int, int> colours;
  for (const auto& p : m.parts) {
    EXPECT_EQ(p.part, "3005");
    ++colours[p.color];
  }
  // The pure face colours map to the table's nearest: red, green-ish, blue, yellow, and so on,
  // plus the inside (dark bluish grey, 72).
  EXPECT_GE(colours.size(), 6u);
  EXPECT_GT(colours[72], 0);
  EXPECT_GT(colours[4], 0);                  // Red
  EXPECT_GT(colours[14] + colours[226], 0);  // Yellow or Bright Light Yellow: #FFFF00 is nearer 226
  // Hollowed by default: fewer bricks than with --solid.
  auto solid = scratch("solid.ldr");
  ASSERT_EQ(run_tool("legolize", {coloured_cube().string(), "--voxels-only", "--height", "20",
                                  "--solid", "-o", solid.string()})
                .exit_code,
            0);
  auto hollow = scratch("hollow.ldr");
  ASSERT_EQ(run_tool("legolize", {coloured_cube().string(), "--voxels-only", "--height", "20", "-o",
                                  hollow.string()})
                .exit_code,
            0);
  EXPECT_LT(ldraw::read_file(hollow).parts.size(), ldraw::read_file(solid).parts.size());
}

// The model must come out turned, never mirrored: LDraw is right-handed with -y up.
TEST(Legolize, OutputIsNotAMirrorImage) {
  auto out = scratch("hand.ldr");
  ASSERT_EQ(run_tool("legolize", {coloured_cube().string(), "--voxels-only", "--height", "10",
                                  "--palette", "4,2,1,14,11,13,72", "-o", out.string()})
                .exit_code,
            0);
  ldraw::Model m = ldraw::read_file(out);
  std::array<double, 3> centre{0, 0, 0};
  std::map<int, std::array<double, 4>> sums;  // colour -> sum of x, y, z and count
  for (const auto& p : m.parts) {
    for (int a = 0; a < 3; ++a) centre[a] += p.transform.pos[a] / double(m.parts.size());
    auto& s = sums[p.color];
    for (int a = 0; a < 3; ++a) s[a] += p.transform.pos[a];
    s[3] += 1;
  }
  auto direction = [&](int colour) {
    const auto& s = sums.at(colour);
    return std::array<double, 3>{s[0] / s[3] - centre[0], s[1] / s[3] - centre[1],
                                 s[2] / s[3] - centre[2]};
  };
  const auto px = direction(2), py = direction(14),
             pz = direction(13);  // green +x, yellow +y, magenta +z
  // In the mesh, x × y = z. A rotation keeps that; a mirror flips its sign.
  const double triple = (px[1] * py[2] - px[2] * py[1]) * pz[0] +
                        (px[2] * py[0] - px[0] * py[2]) * pz[1] +
                        (px[0] * py[1] - px[1] * py[0]) * pz[2];
  EXPECT_GT(triple, 0);
  EXPECT_LT(py[1], 0);  // and up is -y
}

TEST(Legolize, BadInputExitsTwoAndWritesNothing) {
  auto out = scratch("none.ldr");
  auto run = run_tool("legolize", {"/nonexistent/mesh.obj", "--voxels-only", "-o", out.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("/nonexistent/mesh.obj: no such file"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(run_tool("legolize", {coloured_cube().string(), "--voxels-only", "--palette", "4,9999",
                                  "-o", out.string()})
                .exit_code,
            2);
  EXPECT_EQ(run_tool("legolize", {coloured_cube().string(), "--voxels-only", "--height", "5000",
                                  "--max-voxels", "1000", "-o", out.string()})
                .exit_code,
            2);
  EXPECT_EQ(run_tool("legolize",
                     {coloured_cube().string(), "--voxels-only", "-o", "/nonexistent-dir/x.ldr"})
                .exit_code,
            2);
  EXPECT_FALSE(fs::exists(out));
  auto full = run_tool("legolize", {coloured_cube().string(), "-o", out.string()});
  EXPECT_EQ(full.exit_code, 2);
  EXPECT_NE(full.err.find("--voxels-only"), std::string::npos);
}

TEST(Legolize, DefaultColourAndNonFiniteCoordinates) {
  auto obj = scratch("plain.obj");
  std::ofstream(obj) << "v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  auto out = scratch("plain.ldr");
  ASSERT_EQ(run_tool("legolize", {obj.string(), "--voxels-only", "--height", "4", "--solid",
                                  "--palette", "all", "--default-color", "4", "-o", out.string()})
                .exit_code,
            0);
  int red = 0;
  for (const auto& p : ldraw::read_file(out).parts) red += p.color == 4;
  EXPECT_GT(red, 0);  // the uncoloured surface takes the user's default
  EXPECT_EQ(run_tool("legolize",
                     {obj.string(), "--voxels-only", "--default-color", "9999", "-o", out.string()})
                .exit_code,
            2);
  auto nan = scratch("nan.obj");
  std::ofstream(nan) << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n";
  auto run =
      run_tool("legolize", {nan.string(), "--voxels-only", "-o", scratch("nan.ldr").string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_FALSE(fs::exists(scratch("nan.ldr")));
}

TEST(Legolize, TheBunnyVoxelizes) {
  SKIP_WITHOUT_SHARED();
  auto out = scratch("bunny.mpd");
  auto run = run_tool("legolize", {(test::shared_dir() / "meshes" / "bunny.obj").string(),
                                   "--voxels-only", "--height", "40", "-o", out.string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ldraw::Model m = ldraw::read_file(out);
  EXPECT_FALSE(m.has_errors());
  EXPECT_GT(m.parts.size(), 5000u);
  EXPECT_EQ(m.steps.size(), 40u);
}

}  // namespace
}  // namespace lego
