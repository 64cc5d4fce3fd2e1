#pragma once
// A colored triangle mesh, baked into one coordinate frame: what the voxelizer needs of a scene.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace lego::mesh {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};
struct Rgb {
  float r = 0.8f, g = 0.8f, b = 0.8f;  // linear 0..1 as the file gives it
};

struct Triangle {
  std::array<Vec3, 3> v;
  std::array<Rgb, 3> color;  // per corner: vertex colors, else the material's, else the default
  int texture = -1;          // index into Mesh::textures; it takes precedence over `color`
  std::array<std::array<float, 2>, 3> uv{};
};

// An RGB image, rows from the top, sampled with wrap-around (repeat) and bilinear filtering.
struct Texture {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  Rgb sample(float u, float v) const;
};

struct Mesh {
  std::vector<Triangle> triangles;
  std::vector<Texture> textures;
  Vec3 min, max;  // bounding box
  std::string source;
  std::string up;  // which way was taken as up, and why: "+z (the 3MF format's up)"
  // What was read but not used, in words a user can act on: "texture '..\earth.jpg' of
  // material 'globe' not found (looked for ...)". Empty when everything was used.
  std::vector<std::string> warnings;
  // Every file read for it: the mesh, its material libraries, buffers and textures.
  std::vector<std::filesystem::path> files_read;

  // The color at barycentric coordinates (b0, b1, b2) of a triangle: its texture through the
  // UVs, else its corner colors interpolated.
  Rgb color_at(const Triangle& t, double b0, double b1, double b2) const;
};

// An axis of the file's own coordinates, as written in it, and its direction.
struct UpAxis {
  int axis = 1;  // 0 x, 1 y, 2 z
  int sign = 1;  // +1 or -1
};
// "x", "-x", "+y", ... ; nullopt for anything else.
std::optional<UpAxis> parse_up_axis(const std::string& text);
std::string to_string(UpAxis up);  // "+y", "-z"

struct MeshOptions {
  // Which axis of the file points up (the mesh comes back y-up). nullopt: the file's own
  // declaration where it has one (Collada's up_axis, FBX's GlobalSettings) or its format's fixed
  // convention (3MF, AMF, Blender, 3DS: +z; glTF, X3D, VRML: +y), else +y.
  std::optional<UpAxis> up;
  Rgb default_color;  // where the file has no color
  // The file is read first in a child process with this time limit (0: not at all), so that a
  // reader that crashes or hangs on a malformed file (Assimp does, on some) ends in an error
  // naming the file instead of taking the process down.
  double guard_seconds = 120;
};

// Reads any format Assimp reads, triangulated, with node transforms baked in. Throws InputError
// (file as given) for a missing or unreadable file, a file Assimp rejects, crashes or hangs on,
// no triangles, or non-finite coordinates.
Mesh load_mesh(const std::filesystem::path& path, const MeshOptions& options = {});

}  // namespace lego::mesh
