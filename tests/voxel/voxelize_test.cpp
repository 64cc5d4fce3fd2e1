#include <gtest/gtest.h>

#include "test_paths.h"

#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include "core/brick_catalog.h"
#include "core/error.h"
#include "mesh/mesh.h"
#include "voxel/palette.h"
#include "voxel/voxelize.h"

namespace lego::voxel {
namespace {

namespace fs = std::filesystem;
using mesh::Vec3;

fs::path scratch(const std::string& name) {
  return test::scratch("lego_voxel_", name);
}

struct Obj {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;  // 0-based
  std::vector<std::string> material;  // per face, optional
};

Obj uv_sphere(double r, int rings = 48, int segments = 96) {
  Obj o;
  o.v.push_back({0, r, 0});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
      o.v.push_back(
          {r * std::sin(th) * std::cos(ph), r * std::cos(th), r * std::sin(th) * std::sin(ph)});
    }
  o.v.push_back({0, -r, 0});
  const int south = int(o.v.size()) - 1;
  auto at = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) {
    o.f.push_back({0, at(1, j + 1), at(1, j)});
    o.f.push_back({south, at(rings - 1, j), at(rings - 1, j + 1)});
  }
  for (int i = 1; i < rings - 1; ++i)
    for (int j = 0; j < segments; ++j) {
      o.f.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      o.f.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return o;
}

// An axis-aligned box [0, s]³ as 12 triangles, face by face: -x +x -y +y -z +z.
Obj box(double s, bool with_top = true) {
  Obj o;
  for (int i = 0; i < 8; ++i) o.v.push_back({s * (i & 1), s * ((i >> 1) & 1), s * ((i >> 2) & 1)});
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  const char* names[6] = {"minus_x", "plus_x", "minus_y", "plus_y", "minus_z", "plus_z"};
  for (int k = 0; k < 6; ++k) {
    if (!with_top && k == 3) continue;
    o.f.push_back({faces[k][0], faces[k][1], faces[k][2]});
    o.f.push_back({faces[k][0], faces[k][2], faces[k][3]});
    o.material.push_back(names[k]);
    o.material.push_back(names[k]);
  }
  return o;
}

fs::path write_obj(const Obj& o, const std::string& name, const std::string& mtl = "") {
  auto path = scratch(name);
  std::ofstream out(path);
  if (!mtl.empty()) {
    std::ofstream(path.parent_path() / "colors.mtl") << mtl;
    out << "mtllib colors.mtl\n";
  }
  for (const auto& v : o.v) out << "v " << v.x << " " << v.y << " " << v.z << "\n";
  for (size_t i = 0; i < o.f.size(); ++i) {
    if (!o.material.empty() && (i == 0 || o.material[i] != o.material[i - 1]))
      out << "usemtl " << o.material[i] << "\n";
    out << "f " << o.f[i][0] + 1 << " " << o.f[i][1] + 1 << " " << o.f[i][2] + 1 << "\n";
  }
  return path;
}

double voxel_volume(const VoxelGrid& g) {
  return g.stud * g.stud * g.brick;
}

TEST(Voxelize, SolidSphereMatchesItsVolume) {
  const double r = 10;
  // Surface voxels are every voxel the surface touches, half a voxel outside on average: the
  // excess shrinks with resolution (+17% at 24 bricks high), so measure at 60 bricks high.
  VoxelGrid g =
      voxelize(mesh::load_mesh(write_obj(uv_sphere(r), "sphere.obj")), {.height_bricks = 60});
  EXPECT_EQ(g.height, 60);
  EXPECT_EQ(g.width,
            int(std::ceil(20 / g.stud - 1e-9)));  // LEGO proportions: more studs than bricks
  const double expected = 4.0 / 3.0 * std::numbers::pi * r * r * r / voxel_volume(g);
  EXPECT_NEAR(double(g.filled()), expected, 0.10 * expected);
  EXPECT_EQ(g.at(g.width / 2, g.height / 2, g.depth / 2), Cell::Inside);
}

TEST(Voxelize, OpenBoxHoleAndFlippedNormalsStillFill) {
  const double s = 12;
  VoxelGrid open =
      voxelize(mesh::load_mesh(write_obj(box(s, false), "open.obj")), {.height_bricks = 10});
  const size_t all = size_t(open.width) * open.height * open.depth;
  EXPECT_EQ(open.filled(), all);  // the box fills its whole grid, top face or not
  Obj holed = uv_sphere(10);
  holed.f.erase(holed.f.begin() + 200, holed.f.begin() + 260);  // a hole in the northern cap
  for (size_t i = 0; i < holed.f.size(); i += 3)
    std::swap(holed.f[i][1], holed.f[i][2]);  // flip a third
  VoxelGrid g = voxelize(mesh::load_mesh(write_obj(holed, "holed.obj")), {.height_bricks = 60});
  const double expected = 4.0 / 3.0 * std::numbers::pi * 1000 / voxel_volume(g);
  EXPECT_NEAR(double(g.filled()), expected, 0.10 * expected);
}

TEST(Voxelize, ThinWallKeepsItsVoxels) {
  Obj wall;  // a single square, no thickness, standing in the middle of a box's grid
  wall.v = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  wall.f = {{0, 1, 2}, {0, 2, 3}};
  VoxelGrid g = voxelize(mesh::load_mesh(write_obj(wall, "wall.obj")), {.height_bricks = 10});
  EXPECT_EQ(g.count(Cell::Surface), size_t(g.width) * g.height);  // one layer, no gaps
  EXPECT_EQ(g.count(Cell::Inside), 0u);
}

TEST(Voxelize, CubeFacesKeepTheirColours) {
  const char* mtl =
      "newmtl minus_x\nKd 1 0 0\nnewmtl plus_x\nKd 0 1 0\nnewmtl minus_y\nKd 0 0 1\n"
      "newmtl plus_y\nKd 1 1 0\nnewmtl minus_z\nKd 0 1 1\nnewmtl plus_z\nKd 1 0 1\n";
  VoxelGrid g =
      voxelize(mesh::load_mesh(write_obj(box(12, true), "cube.obj", mtl)), {.height_bricks = 12});
  const int cx = g.width / 2, cy = g.height / 2, cz = g.depth / 2;
  auto rgb = [&](int x, int y, int z) {
    EXPECT_EQ(g.at(x, y, z), Cell::Surface) << x << " " << y << " " << z;
    return g.color[g.index(x, y, z)];
  };
  auto expect = [](mesh::Rgb c, float r, float gg, float b) {
    EXPECT_NEAR(c.r, r, 0.01);
    EXPECT_NEAR(c.g, gg, 0.01);
    EXPECT_NEAR(c.b, b, 0.01);
  };
  expect(rgb(0, cy, cz), 1, 0, 0);
  expect(rgb(g.width - 1, cy, cz), 0, 1, 0);
  expect(rgb(cx, 0, cz), 0, 0, 1);
  expect(rgb(cx, g.height - 1, cz), 1, 1, 0);
  expect(rgb(cx, cy, 0), 0, 1, 1);
  expect(rgb(cx, cy, g.depth - 1), 1, 0, 1);
}

TEST(Voxelize, HollowingLeavesAConnectedShell) {
  VoxelGrid g =
      voxelize(mesh::load_mesh(write_obj(uv_sphere(15), "big.obj")), {.height_bricks = 30});
  const size_t solid = g.filled();
  hollow(g, 3);
  EXPECT_LT(g.filled(), solid);
  EXPECT_EQ(g.at(g.width / 2, g.height / 2, g.depth / 2), Cell::Empty);
  // Every kept voxel is within 3 layers: its 6-neighbour distance to a surface voxel is < 3.
  std::vector<int> dist(g.cells.size(), -1);
  std::deque<std::array<int, 3>> q;
  for (int y = 0; y < g.height; ++y)
    for (int z = 0; z < g.depth; ++z)
      for (int x = 0; x < g.width; ++x)
        if (g.at(x, y, z) == Cell::Surface) dist[g.index(x, y, z)] = 0, q.push_back({x, y, z});
  size_t reached = q.size();
  while (!q.empty()) {
    auto [x, y, z] = q.front();
    q.pop_front();
    for (auto [dx, dy, dz] :
         {std::array{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}})
      if (g.at(x + dx, y + dy, z + dz) == Cell::Inside &&
          dist[g.index(x + dx, y + dy, z + dz)] < 0) {
        dist[g.index(x + dx, y + dy, z + dz)] = dist[g.index(x, y, z)] + 1;
        EXPECT_LT(dist[g.index(x + dx, y + dy, z + dz)], 3);
        q.push_back({x + dx, y + dy, z + dz});
        ++reached;
      }
  }
  EXPECT_EQ(reached, g.filled());
  EXPECT_GT(g.count(Cell::Inside), 0u);  // the shell is thicker than the surface
  // And it is one piece: a flood fill over kept voxels from one of them reaches all.
  std::vector<char> seen(g.cells.size(), 0);
  size_t start = 0;
  while (g.cells[start] == Cell::Empty) ++start;
  std::vector<size_t> stack{start};
  seen[start] = 1;
  size_t count = 0;
  while (!stack.empty()) {
    size_t id = stack.back();
    stack.pop_back();
    ++count;
    const int x = int(id % g.width), z = int((id / g.width) % g.depth),
              y = int(id / (size_t(g.width) * g.depth));
    for (auto [dx, dy, dz] :
         {std::array{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}})
      if (g.at(x + dx, y + dy, z + dz) != Cell::Empty && !seen[g.index(x + dx, y + dy, z + dz)]) {
        seen[g.index(x + dx, y + dy, z + dz)] = 1;
        stack.push_back(g.index(x + dx, y + dy, z + dz));
      }
  }
  EXPECT_EQ(count, g.filled());
}

TEST(Mesh, ReadsStlAndPlyWithVertexColours) {
  auto stl = scratch("tetra.stl");
  std::ofstream(stl) << "solid t\n"
                        "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
                        "0\nendloop\nendfacet\n"
                        "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 1 0 "
                        "0\nendloop\nendfacet\n"
                        "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 0 0 "
                        "1\nendloop\nendfacet\n"
                        "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 0 1\nvertex 0 1 "
                        "0\nendloop\nendfacet\n"
                        "endsolid t\n";
  EXPECT_EQ(mesh::load_mesh(stl).triangles.size(), 4u);
  auto ply = scratch("tri.ply");
  std::ofstream(ply)
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0 255 0 0\n1 0 0 255 0 0\n0 1 0 255 0 0\n3 0 1 2\n";
  auto m = mesh::load_mesh(ply);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_NEAR(m.triangles[0].color[0].r, 1.0, 1e-6);
  EXPECT_NEAR(m.triangles[0].color[0].g, 0.0, 1e-6);
  // z up in the file: the mesh comes back y up.
  auto z_up = mesh::load_mesh(ply, {.up = mesh::UpAxis{2, 1}, .default_color = {}});
  EXPECT_NEAR(z_up.triangles[0].v[2].z, -1.0, 1e-9);
}

TEST(Mesh, BadInputIsAClearError) {
  auto expect_error = [](const fs::path& p, const std::string& needle) {
    try {
      mesh::load_mesh(p);
      ADD_FAILURE() << "no error for " << p;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error("/nonexistent/mesh.obj", "no such file");
  auto garbage = scratch("garbage.stl");
  std::ofstream(garbage) << "this is not a mesh at all";
  expect_error(garbage, "cannot be read");
  auto points = scratch("points.obj");
  std::ofstream(points) << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_error(points, "");
  Obj s = uv_sphere(10);
  try {
    voxelize(mesh::load_mesh(write_obj(s, "big.obj")),
             {.height_bricks = 400, .max_voxels = 1000000});
    ADD_FAILURE() << "no budget error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("budget"), std::string::npos);
  }
}

}  // namespace
}  // namespace lego::voxel

namespace lego::voxel {
namespace {

TEST(Palette, CiedeTwoThousandMatchesPublishedPairs) {
  // Sharma, Wu & Dalal (2005), test data pairs 1, 7 and 17.
  EXPECT_NEAR(ciede2000({50, 2.6772, -79.7751}, {50, 0, -82.7485}), 2.0425, 1e-4);
  EXPECT_NEAR(ciede2000({50, 0, 0}, {50, -1, 2}), 2.3669, 1e-4);
  EXPECT_NEAR(ciede2000({50, 2.5, 0}, {73, 25, -18}), 27.1492, 1e-4);
}

TEST(Palette, NearestLDrawColours) {
  const auto& table = ldraw::ColorTable::standard();
  Palette paper = Palette::paper(table);
  EXPECT_EQ(paper.codes().size(), 8u);
  EXPECT_EQ(paper.nearest({1, 1, 1}), 15);
  EXPECT_EQ(paper.nearest({0.05f, 0.05f, 0.05f}), 0);
  EXPECT_EQ(paper.nearest({0.8f, 0.05f, 0.05f}), 4);
  EXPECT_EQ(paper.nearest({0.1f, 0.3f, 0.8f}), 1);
  EXPECT_EQ(paper.nearest({0.9f, 0.5f, 0.1f}), 25);
  EXPECT_EQ(Palette::of({4, 14}, table).nearest({1, 1, 1}),
            14);  // only what it has: the lighter one
  EXPECT_THROW(Palette::of({4, 9999}, table), InputError);
  EXPECT_GT(Palette::all(table).codes().size(), 30u);
  // The table's Trans_Clear (booklets draw with it) is no colour a sculpture is built in.
  ASSERT_NE(table.find(47), nullptr);
  EXPECT_LT(table.find(47)->alpha, 255);
  const auto all = Palette::all(table).codes();
  EXPECT_EQ(std::count(all.begin(), all.end(), 47), 0);
  EXPECT_EQ(Palette::all(table).nearest({1, 1, 1}), 15);
}

}  // namespace
}  // namespace lego::voxel

namespace lego::voxel {
namespace {

// Colours a mesh really has, to the colour a builder would pick (issue 18: navy oceans came out
// black and skin orange with the paper's eight).
TEST(Palette, CurrentColoursKeepNavyBlueAndSkinSkin) {
  const auto& table = ldraw::ColorTable::standard();
  const mesh::Rgb navy{0.0f, 0.0f, 0.5f}, ocean{0.05f, 0.12f, 0.35f}, skin{1.0f, 0.8f, 0.65f},
      grey{0.6f, 0.6f, 0.6f};
  const Palette current = Palette::current(table);
  EXPECT_TRUE(current.nearest(navy) == 272 || current.nearest(navy) == 1) << current.nearest(navy);
  EXPECT_EQ(current.nearest(ocean), 272);
  EXPECT_EQ(current.nearest(skin), 78);  // Light Nougat
  EXPECT_EQ(current.nearest(grey), 71);  // Light Bluish Grey
  const mesh::Rgb light_grey{0.8f, 0.8f, 0.8f}, dark_grey{0.3f, 0.3f, 0.3f};
  EXPECT_TRUE(current.nearest(light_grey) == 15 || current.nearest(light_grey) == 71);
  EXPECT_EQ(current.nearest(dark_grey), 72);
  EXPECT_EQ(current.nearest({0.35f, 0.02f, 0.02f}), 320);  // Dark Red
  EXPECT_EQ(current.nearest({0.05f, 0.2f, 0.05f}), 288);   // Dark Green
  EXPECT_EQ(current.nearest({0.85f, 0.75f, 0.55f}), 19);   // Tan
  EXPECT_EQ(current.nearest({1.0f, 0.6f, 0.7f}), 29);      // Bright Pink
  EXPECT_EQ(current.nearest({0.0f, 0.45f, 0.45f}), 3);     // Dark Turquoise
  const Palette paper = Palette::paper(table);
  EXPECT_EQ(paper.nearest(navy), 1) << "navy with only the paper's eight is still blue";
  EXPECT_EQ(paper.nearest(grey), 15) << "grey without a grey is white, never orange";
}

TEST(Palette, CurrentColoursAreInProductionAndOnBrickLink) {
  const auto& table = ldraw::ColorTable::standard();
  const std::vector<int>& codes = Palette::current_codes();
  for (int retired : {6, 7, 8, 11, 13, 22})
    EXPECT_EQ(std::count(codes.begin(), codes.end(), retired), 0) << retired;
  for (int wanted : {70, 71, 72, 19, 1, 272, 28})
    EXPECT_EQ(std::count(codes.begin(), codes.end(), wanted), 1) << wanted;
  std::ifstream csv(default_parts_dir() / "bricklink.csv");
  ASSERT_TRUE(csv) << "ldraw_parts/bricklink.csv";
  std::map<int, int> bricklink;
  for (std::string line; std::getline(csv, line);)
    if (line.rfind("color,", 0) == 0) {
      const int ldraw = std::stoi(line.substr(6));
      bricklink[ldraw] = std::stoi(line.substr(line.find(',', 6) + 1));
    }
  for (int code : codes) {
    EXPECT_TRUE(table.find(code)) << code;
    EXPECT_TRUE(bricklink.count(code)) << "LDraw " << code << " has no BrickLink colour";
  }
  // Spot checks against BrickLink's colour guide.
  EXPECT_EQ(bricklink[70], 88);   // Reddish Brown
  EXPECT_EQ(bricklink[71], 86);   // Light Bluish Gray
  EXPECT_EQ(bricklink[272], 63);  // Dark Blue
  EXPECT_EQ(bricklink[78], 90);   // Light Nougat
  EXPECT_EQ(Palette::paper(table).with(71, table).codes().size(), 9u);
  EXPECT_EQ(Palette::current(table).with(71, table).codes().size(), codes.size());
}

}  // namespace
}  // namespace lego::voxel
