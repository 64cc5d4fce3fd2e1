#include "mesh/mesh.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <map>
#include <system_error>

#include <sys/wait.h>
#include <unistd.h>

#include "core/error.h"
#include "mesh/image.h"

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
  // A file without materials gets Assimp's own grey "DefaultMaterial": that is no color given.
  aiString name;
  if (m && m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
      std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME)
    return fallback;
  aiColor4D c;
  if (m && (aiGetMaterialColor(m, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
            aiGetMaterialColor(m, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS))
    return {c.r, c.g, c.b};
  return fallback;
}

// The diffuse or base color map of a material, loaded once per path; -1 when there is none.
int material_texture(const aiScene* scene, const aiMaterial* m, const std::filesystem::path& dir,
                     Mesh& out, std::map<std::string, int>& loaded) {
  aiString name;
  if (!m || (m->GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS &&
             m->GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS))
    return -1;
  const std::string key = name.C_Str();
  if (auto it = loaded.find(key); it != loaded.end()) return it->second;
  Texture t;
  std::string why;
  if (const aiTexture* embedded = scene->GetEmbeddedTexture(name.C_Str())) {
    if (embedded->mHeight == 0) {  // compressed (PNG, JPEG...): mWidth is its size in bytes
      decode_image(reinterpret_cast<const unsigned char*>(embedded->pcData), embedded->mWidth, t,
                   why);
    } else {
      t.width = int(embedded->mWidth);
      t.height = int(embedded->mHeight);
      for (unsigned i = 0; i < embedded->mWidth * embedded->mHeight; ++i)
        t.rgb.insert(t.rgb.end(),
                     {embedded->pcData[i].r, embedded->pcData[i].g, embedded->pcData[i].b});
    }
  } else {
    std::string file = key;
    std::replace(file.begin(), file.end(), '\\', '/');
    load_image(dir / file, t, why);
  }
  int index = -1;
  if (t.width > 0) {
    index = int(out.textures.size());
    out.textures.push_back(std::move(t));
  }
  loaded[key] = index;  // a texture that cannot be read leaves the material color in charge
  return index;
}

}  // namespace

Rgb Texture::sample(float u, float v) const {
  // Texture v runs upwards, image rows downwards; repeat outside [0, 1].
  const float x = (u - std::floor(u)) * width - 0.5f, y = (1 - (v - std::floor(v))) * height - 0.5f;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  auto px = [&](int i, int j, int c) {
    i = ((i % width) + width) % width;
    j = ((j % height) + height) % height;
    return rgb[(size_t(j) * width + i) * 3 + c] / 255.0f;
  };
  float out[3];
  for (int c = 0; c < 3; ++c)
    out[c] = (1 - fy) * ((1 - fx) * px(x0, y0, c) + fx * px(x0 + 1, y0, c)) +
             fy * ((1 - fx) * px(x0, y0 + 1, c) + fx * px(x0 + 1, y0 + 1, c));
  return {out[0], out[1], out[2]};
}

Rgb Mesh::color_at(const Triangle& t, double b0, double b1, double b2) const {
  if (t.texture >= 0) {
    const float u = float(b0 * t.uv[0][0] + b1 * t.uv[1][0] + b2 * t.uv[2][0]);
    const float v = float(b0 * t.uv[0][1] + b1 * t.uv[1][1] + b2 * t.uv[2][1]);
    return textures[t.texture].sample(u, v);
  }
  return {float(b0 * t.color[0].r + b1 * t.color[1].r + b2 * t.color[2].r),
          float(b0 * t.color[0].g + b1 * t.color[1].g + b2 * t.color[2].g),
          float(b0 * t.color[0].b + b1 * t.color[1].b + b2 * t.color[2].b)};
}

namespace {

Mesh read_mesh(const std::filesystem::path& path, const MeshOptions& options);

// Reads the file in a child process first: a crash, a hang past the time limit or an allocation
// that fails there becomes an InputError here. The child exits without cleaning up (_exit), and
// this runs before any thread of ours starts.
void read_in_child_first(const std::filesystem::path& path, const MeshOptions& options) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return;  // no child to spare: read it here as before
  if (pid == 0) {
    ::alarm(unsigned(std::ceil(options.guard_seconds)));
    int code = 0;
    try {
      read_mesh(path, options);
    } catch (const InputError&) {
      code = 0;  // a clean error: the parent finds it again and says it
    } catch (const std::bad_alloc&) {
      code = 3;
    } catch (...) {
      code = 4;
    }
    ::_exit(code);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  std::string why;
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM)
    why = fmt::format("reading it did not end within {:g} s (the reader hangs on this file)",
                      options.guard_seconds);
  else if (WIFSIGNALED(status))
    why = fmt::format("the reader crashed on this file ({})", ::strsignal(WTERMSIG(status)));
  else if (WEXITSTATUS(status) == 3)
    why = "reading it needs more memory than there is (a size in the file is out of bounds)";
  else
    why = "the reader failed on this file";
  throw InputError(path.string(), 0, "the mesh cannot be read: " + why);
}

}  // namespace

Mesh load_mesh(const std::filesystem::path& path, const MeshOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string(), 0,
                     std::filesystem::exists(path, ec) ? "not a regular file" : "no such file");
  if (options.guard_seconds > 0) read_in_child_first(path, options);
  return read_mesh(path, options);
}

namespace {

Mesh read_mesh(const std::filesystem::path& path, const MeshOptions& options) {
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
  std::map<std::string, int> loaded;
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    const aiMaterial* material = scene->mMaterials[m->mMaterialIndex];
    const Rgb base = material_color(material, options.default_color);
    const bool vertex_colors = m->HasVertexColors(0);
    // Most specific first: a texture through UVs, then vertex colors, then the material's.
    const int texture = m->HasTextureCoords(0)
                            ? material_texture(scene, material, path.parent_path(), out, loaded)
                            : -1;
    for (unsigned fi = 0; fi < m->mNumFaces; ++fi) {
      const aiFace& f = m->mFaces[fi];
      if (f.mNumIndices != 3) continue;  // points and lines carry no surface
      Triangle t;
      t.texture = texture;
      for (int k = 0; k < 3; ++k) {
        const unsigned vi = f.mIndices[k];
        if (texture >= 0) t.uv[k] = {m->mTextureCoords[0][vi].x, m->mTextureCoords[0][vi].y};
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

}  // namespace

}  // namespace lego::mesh
