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
};

struct Mesh {
  std::vector<Triangle> triangles;
  Vec3 min, max;  // bounding box
  std::string source;
};

enum class UpAxis { X, Y, Z };

struct MeshOptions {
  UpAxis up = UpAxis::Y;  // which axis of the file points up; the mesh comes back y-up
  Rgb default_color;      // where the file has no color
};

// Reads any format Assimp reads, triangulated, with node transforms baked in. Throws InputError
// (file as given) for a missing or unreadable file, a file Assimp rejects, no triangles, or
// non-finite coordinates.
Mesh load_mesh(const std::filesystem::path& path, const MeshOptions& options = {});

}  // namespace lego::mesh
