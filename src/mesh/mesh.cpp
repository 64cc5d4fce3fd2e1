#include "mesh/mesh.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <system_error>

#include "core/error.h"

namespace lego::mesh {
namespace {

Vec3 to_y_up(const aiVector3D& p, UpAxis up) {
  switch (up) {
    case UpAxis::X:
      return {-p.y, p.x, p.z};
    case UpAxis::Z:
      return {p.x, p.z, -p.y};
    case UpAxis::Y:
      break;
  }
  return {p.x, p.y, p.z};
}

Rgb material_color(const aiMaterial* m, const Rgb& fallback) {
  aiColor4D c;
  if (m && (aiGetMaterialColor(m, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
            aiGetMaterialColor(m, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS))
    return {c.r, c.g, c.b};
  return fallback;
}

}  // namespace

Mesh load_mesh(const std::filesystem::path& path, const MeshOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string(), 0,
                     std::filesystem::exists(path, ec) ? "not a regular file" : "no such file");
  Assimp::Importer importer;
  // PreTransformVertices bakes every node's transform into its meshes: one frame for all.
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                           aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw InputError(path.string(), 0,
                     fmt::format("the mesh cannot be read: {}", importer.GetErrorString()));
  Mesh out;
  out.source = path.string();
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    const Rgb base = material_color(scene->mMaterials[m->mMaterialIndex], options.default_color);
    const bool vertex_colors = m->HasVertexColors(0);
    for (unsigned fi = 0; fi < m->mNumFaces; ++fi) {
      const aiFace& f = m->mFaces[fi];
      if (f.mNumIndices != 3) continue;  // points and lines carry no surface
      Triangle t;
      for (int k = 0; k < 3; ++k) {
        const unsigned vi = f.mIndices[k];
        t.v[k] = to_y_up(m->mVertices[vi], options.up);
        if (!std::isfinite(t.v[k].x) || !std::isfinite(t.v[k].y) || !std::isfinite(t.v[k].z))
          throw InputError(path.string(), 0, "the mesh has a vertex with a non-finite coordinate");
        if (vertex_colors) {
          const aiColor4D& c = m->mColors[0][vi];
          t.color[k] = {c.r, c.g, c.b};
        } else {
          t.color[k] = base;
        }
      }
      out.triangles.push_back(t);
    }
  }
  if (out.triangles.empty()) throw InputError(path.string(), 0, "the mesh has no triangles");
  out.min = out.max = out.triangles[0].v[0];
  for (const auto& t : out.triangles)
    for (const auto& p : t.v) {
      out.min = {std::min(out.min.x, p.x), std::min(out.min.y, p.y), std::min(out.min.z, p.z)};
      out.max = {std::max(out.max.x, p.x), std::max(out.max.y, p.y), std::max(out.max.z, p.z)};
    }
  return out;
}

}  // namespace lego::mesh
