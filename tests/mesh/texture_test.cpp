// Textures through UVs, external and embedded; glTF with node transforms; size options.
#include <gtest/gtest.h>

#include "test_paths.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "core/error.h"
#include "mesh/mesh.h"
#include "voxel/voxelize.h"

namespace lego::mesh {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return test::scratch("lego_texture_", name);
}

// 4 x 1 pixels: red, red, blue, blue. Left half of u red, right half blue.
std::vector<unsigned char> red_blue_png() {
  const unsigned char px[12] = {255, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0, 255};
  std::vector<unsigned char> png;
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(ctx);
        out->insert(out->end(), static_cast<unsigned char*>(data),
                    static_cast<unsigned char*>(data) + size);
      },
      &png, 4, 1, 3, px, 12);
  return png;
}

std::string base64(const void* data, size_t size) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  for (size_t i = 0; i < size; i += 3) {
    unsigned v = p[i] << 16 | (i + 1 < size ? p[i + 1] << 8 : 0) | (i + 2 < size ? p[i + 2] : 0);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < size ? table[(v >> 6) & 63] : '=';
    out += i + 2 < size ? table[v & 63] : '=';
  }
  return out;
}

// The voxel colours along x in the middle row of a vertical quad in the xy plane.
void expect_red_left_blue_right(const Mesh& m) {
  voxel::VoxelGrid g = voxel::voxelize(m, {.height_bricks = 8});
  const int y = g.height / 2;
  int red = 0, blue = 0;
  for (int x = 0; x < g.width; ++x) {
    ASSERT_EQ(g.at(x, y, 0), voxel::Cell::Surface) << x;
    const Rgb c = g.color[g.index(x, y, 0)];
    if (x > 0 && x < g.width / 2 - 1) {  // clear of the blends at the seams
      EXPECT_GT(c.r, 0.8) << x;
    }
    if (x > g.width / 2 && x < g.width - 1) {
      EXPECT_GT(c.b, 0.8) << x;
    }
    red += c.r > c.b;
    blue += c.b > c.r;
  }
  EXPECT_GT(red, g.width / 3);
  EXPECT_GT(blue, g.width / 3);
}

TEST(Texture, QuadFollowsItsExternalTexture) {
  auto png = red_blue_png();
  std::ofstream(scratch("red_blue.png"), std::ios::binary)
      .write(reinterpret_cast<const char*>(png.data()), png.size());
  std::ofstream(scratch("quad.mtl")) << "newmtl tex\nKd 1 1 1\nmap_Kd red_blue.png\n";
  auto obj = scratch("quad.obj");
  std::ofstream(obj) << "mtllib quad.mtl\nv 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\n"
                        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tex\nf 1/1 2/2 3/3 4/4\n";
  Mesh m = load_mesh(obj);
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(m.textures[0].width, 4);
  expect_red_left_blue_right(m);
}

// An OBJ whose material library is not there: Assimp goes on silently with the default colour;
// the mesh says so, by file and line, and whether the OBJ's own .mtl stood in for it.
TEST(Texture, AMissingMaterialLibraryIsAWarning) {
  auto obj = scratch("lonely.obj");
  fs::remove(scratch("lonely.mtl"));
  const std::string text = "v 0 0 0\nv 10 0 0\nv 10 10 0\nmtllib gone.mtl\nusemtl red\nf 1 2 3\n";
  std::ofstream(obj) << text;
  Mesh m = load_mesh(obj);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("lonely.obj:4: material library 'gone.mtl' not found (nor "
                               "lonely.mtl)"),
            std::string::npos)
      << m.warnings[0];
  std::ofstream(scratch("lonely.mtl")) << "newmtl red\nKd 1 0 0\n";
  m = load_mesh(obj);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("its materials are read from lonely.mtl"), std::string::npos);
  std::ofstream(scratch("gone.mtl")) << "newmtl red\nKd 1 0 0\n";
  EXPECT_TRUE(load_mesh(obj).warnings.empty());
  fs::remove(scratch("gone.mtl"));
  fs::remove(scratch("lonely.mtl"));
}

TEST(Texture, GltfEmbeddedTextureAndNodeTransforms) {
  const float positions[12] = {0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0};
  const float uvs[8] = {0, 1, 1, 1, 1, 0, 0, 0};  // glTF's v runs down the image
  const unsigned short indices[6] = {0, 1, 2, 0, 2, 3};
  std::vector<unsigned char> buffer(sizeof positions + sizeof uvs + sizeof indices);
  std::memcpy(buffer.data(), positions, sizeof positions);
  std::memcpy(buffer.data() + sizeof positions, uvs, sizeof uvs);
  std::memcpy(buffer.data() + sizeof positions + sizeof uvs, indices, sizeof indices);
  auto png = red_blue_png();
  auto path = scratch("quads.gltf");
  std::ofstream(path) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0, 0, 30]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}],
    "images": [{"uri": "data:image/png;base64,)"
                      << base64(png.data(), png.size()) << R"("}],
    "buffers": [{"byteLength": )"
                      << buffer.size() << R"(, "uri": "data:application/octet-stream;base64,)"
                      << base64(buffer.data(), buffer.size()) << R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                   "min": [0, 0, 0], "max": [10, 10, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
  Mesh both = load_mesh(path);
  EXPECT_EQ(both.triangles.size(), 4u);  // the mesh twice, once per node
  EXPECT_DOUBLE_EQ(both.max.z, 30);      // the second node's translation is baked in
  ASSERT_EQ(both.textures.size(), 1u);   // decoded from the embedded PNG
  Mesh first = both;
  first.triangles.resize(2);
  first.max.z = 0;
  expect_red_left_blue_right(first);
}

// PLY and OFF files with no colour come out in the default colour: Assimp's readers make up an
// unnamed material of their own for them (PLY white, OFF 0.6 grey), which is no colour the file
// gives. A PLY that declares a material keeps it.
TEST(Texture, PlyAndOffWithoutColoursTakeTheDefaultColour) {
  MeshOptions pink;
  pink.default_color = {1.0f, 0.5f, 0.75f};
  auto expect_pink = [&](const fs::path& file) {
    Mesh m = load_mesh(file, pink);
    ASSERT_FALSE(m.triangles.empty()) << file;
    const Rgb c = m.color_at(m.triangles[0], 1.0 / 3, 1.0 / 3, 1.0 / 3);
    EXPECT_FLOAT_EQ(c.r, 1.0f) << file;
    EXPECT_FLOAT_EQ(c.g, 0.5f) << file;
    EXPECT_FLOAT_EQ(c.b, 0.75f) << file;
  };
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n";
  auto ply = scratch("plain.ply");
  std::ofstream(ply) << ply_head << "end_header\n0 0 0\n10 0 0\n10 10 0\n3 0 1 2\n";
  expect_pink(ply);
  auto off = scratch("plain.off");
  std::ofstream(off) << "OFF\n3 1 0\n0 0 0\n10 0 0\n10 10 0\n3 0 1 2\n";
  expect_pink(off);
  // A vertex colour is the file's own: it stays.
  auto coloured = scratch("coloured.ply");
  std::ofstream(coloured)
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0 0 0 255\n10 0 0 0 0 255\n10 10 0 0 0 255\n3 0 1 2\n";
  Mesh m = load_mesh(coloured, pink);
  const Rgb c = m.color_at(m.triangles[0], 1.0 / 3, 1.0 / 3, 1.0 / 3);
  EXPECT_FLOAT_EQ(c.b, 1.0f);
  EXPECT_FLOAT_EQ(c.r, 0.0f);
}

// A zipped Collada file (.zae) declares its up axis in the DAE it holds, as a .dae does.
TEST(Texture, AZippedColladaFileHasTheUpOfItsDae) {
  const fs::path duck = "/usr/share/assimp/models/Collada/duck.zae";
  if (!fs::exists(duck)) GTEST_SKIP() << duck << " is not installed (assimp-testmodels)";
  Mesh m = load_mesh(duck);
  EXPECT_NE(m.up.find("the file's up_axis"), std::string::npos) << m.up;
}

TEST(Texture, SizeAndScaleKeepTheAspect) {
  auto obj = scratch("box.obj");
  std::ofstream(obj)
      << "v 0 0 0\nv 40 0 0\nv 40 12 0\nv 0 12 0\nv 0 0 20\nv 40 0 20\nv 40 12 20\nv 0 12 20\n"
         "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n";
  Mesh m = load_mesh(obj);
  // 40 x 12 x 20 mm at 1 mm per unit: 5 studs x 1.25 bricks x 2.5 studs.
  voxel::VoxelGrid scaled = voxel::voxelize(
      m, {.height_bricks = 20, .fit = {0, 0, 0}, .mm_per_unit = 1, .max_voxels = 1000});
  EXPECT_EQ(scaled.width, 5);
  EXPECT_EQ(scaled.height, 2);
  EXPECT_EQ(scaled.depth, 3);
  // Fit in 10 studs x 10 bricks x 10 studs: the width decides.
  voxel::VoxelGrid fitted = voxel::voxelize(
      m, {.height_bricks = 20, .fit = {10, 10, 10}, .mm_per_unit = 0, .max_voxels = 100000});
  EXPECT_EQ(fitted.width, 10);
  EXPECT_LE(fitted.height, 10);
  EXPECT_EQ(fitted.depth, 5);
}

}  // namespace
}  // namespace lego::mesh
