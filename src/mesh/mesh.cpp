#include "mesh/mesh.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <system_error>

#include <sys/wait.h>
#include <unistd.h>

#include "core/case_insensitive_paths.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/stop.h"
#include "core/text.h"
#include "mesh/image.h"

namespace lego::mesh {
namespace {

// The rotation that turns `up` to +y (a rotation, never a mirror: det +1).
Vec3 to_y_up(const aiVector3D& p, UpAxis up) {
  if (up.axis == 0) return up.sign > 0 ? Vec3{-p.y, p.x, p.z} : Vec3{p.y, -p.x, p.z};
  if (up.axis == 2) return up.sign > 0 ? Vec3{p.x, p.z, -p.y} : Vec3{p.x, -p.z, p.y};
  return up.sign > 0 ? Vec3{p.x, p.y, p.z} : Vec3{p.x, -p.y, -p.z};
}

// The up axis the file declares, or its format's convention, with the reason in words. Collada's
// up_axis is applied by Assimp itself (when --up is not given), so what Assimp returns is +y.
std::pair<UpAxis, std::string> declared_up(const aiScene* scene,
                                           const std::filesystem::path& path) {
  const std::string ext = ascii_lower(path.extension().string());
  int32_t axis = -1, sign = 1;
  if (scene->mMetaData && scene->mMetaData->Get("UpAxis", axis) && axis >= 0 && axis <= 2) {
    scene->mMetaData->Get("UpAxisSign", sign);
    const UpAxis up{int(axis), sign < 0 ? -1 : 1};
    return {up, fmt::format("{} (the file's GlobalSettings)", to_string(up))};
  }
  if (ext == ".dae" || ext == ".zae") return {{1, 1}, "+y (the file's up_axis, applied by Assimp)"};
  for (const char* z_up : {".3mf", ".amf", ".blend", ".3ds", ".max"})
    if (ext == z_up) return {{2, 1}, fmt::format("+z (the {} format's up)", ext.substr(1))};
  for (const char* y_up : {".gltf", ".glb", ".x3d", ".wrl", ".x3dv"})
    if (ext == y_up) return {{1, 1}, fmt::format("+y (the {} format's up)", ext.substr(1))};
  return {{1, 1}, "+y (the file declares no up axis; --up names another)"};
}

// Whether the file's format can name a surface colour at all. The OFF format cannot, and a PLY
// only through an `element material` in its header (vertex colours are read apart); for these
// Assimp's readers make up an unnamed material of their own (PLY white, OFF 0.6 grey), which is no
// colour the file gives.
bool format_names_materials(const std::filesystem::path& path) {
  const std::string ext = ascii_lower(path.extension().string());
  if (ext == ".off") return false;
  if (ext != ".ply") return true;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int n = 0; n < 10000 && std::getline(in, line); ++n) {
    const std::string t = ascii_lower(line);
    if (t.rfind("end_header", 0) == 0) break;
    if (t.rfind("element material", 0) == 0) return true;
  }
  return false;
}

Rgb material_color(const aiMaterial* m, const Rgb& fallback, bool format_names_materials) {
  // A file without materials gets Assimp's own grey "DefaultMaterial": that is no color given.
  aiString name;
  const bool named = m && m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS;
  if (named && std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME) return fallback;
  if (!named && !format_names_materials) return fallback;
  aiColor4D c;
  if (m && (aiGetMaterialColor(m, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
            aiGetMaterialColor(m, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS))
    return {c.r, c.g, c.b};
  return fallback;
}

// Where a texture a material names is on disk, as DCC tools and LDraw users expect to find it:
// Windows separators and drive letters, any case, absolute or relative to the mesh's folder, a
// root-relative "\\..\\maps\\x.jpg" taken as relative, and at last the file name alone in the
// mesh's folder or below it. `looked` lists what was tried, for the warning.
std::optional<std::filesystem::path> find_texture(const std::string& name,
                                                  const std::filesystem::path& dir,
                                                  CaseInsensitivePaths& paths,
                                                  std::vector<std::string>& looked) {
  namespace fs = std::filesystem;
  std::string file = name;
  std::replace(file.begin(), file.end(), '\\', '/');
  if (ascii_lower(file).rfind("file://", 0) == 0) file = file.substr(7);
  const bool drive =
      file.size() >= 2 && std::isalpha(static_cast<unsigned char>(file[0])) && file[1] == ':';
  if (drive) file = file.substr(2);
  std::vector<fs::path> candidates;
  std::string relative = file;
  while (!relative.empty() && relative.front() == '/') relative.erase(0, 1);
  if (!file.empty() && file.front() == '/') candidates.push_back(file);
  if (!relative.empty()) candidates.push_back(dir / relative);
  const fs::path leaf = fs::path(relative).filename();
  if (!leaf.empty()) candidates.push_back(dir / leaf);
  for (const fs::path& c : candidates) {
    looked.push_back(c.lexically_normal().string());
    std::error_code ec;
    if (auto found = paths.find(c); found && fs::is_regular_file(*found, ec)) return found;
  }
  if (leaf.empty()) return std::nullopt;
  // An absolute path from another machine ("D:\\work\\models\\OBJ\\tex.jpg" in an FBX next to
  // an OBJ folder): its trailing folders, longest first, under the mesh folder's parents.
  const fs::path tail_of = fs::path(relative).parent_path();
  std::vector<fs::path> folders(tail_of.begin(), tail_of.end());
  fs::path above = dir.lexically_normal();
  for (int up = 0; up < 3 && !folders.empty() && above.has_relative_path(); ++up) {
    above = above.parent_path();
    for (size_t first = 0; first < folders.size(); ++first) {
      fs::path c = above;
      for (size_t i = first; i < folders.size(); ++i) c /= folders[i];
      c /= leaf;
      std::error_code ec;
      if (auto found = paths.find(c); found && fs::is_regular_file(*found, ec)) return found;
    }
    looked.push_back((above / "…" / folders.back() / leaf).string());
  }
  // The file name alone, anywhere below the mesh's folder (a "textures" or "maps" folder).
  const std::string wanted = ascii_lower(leaf.string());
  std::error_code ec;
  int seen = 0;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec),
       end;
       !ec && it != end && seen < 10000; it.increment(ec), ++seen) {
    if (it.depth() >= 3) it.disable_recursion_pending();
    if (ascii_lower(it->path().filename().string()) == wanted && it->is_regular_file(ec))
      return it->path();
  }
  looked.push_back(dir.string() + "/**/" + leaf.string());
  return std::nullopt;
}

// The diffuse or base color map of a material, loaded once per name; -1 when there is none or
// it cannot be read (then a warning names it and the material colour stays in charge).
int material_texture(const aiScene* scene, const aiMaterial* m, const std::filesystem::path& dir,
                     Mesh& out, std::map<std::string, int>& loaded, CaseInsensitivePaths& paths) {
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
      if (!decode_image(reinterpret_cast<const unsigned char*>(embedded->pcData), embedded->mWidth,
                        t, why))
        why = "the embedded image cannot be decoded: " + why;
    } else {
      t.width = int(embedded->mWidth);
      t.height = int(embedded->mHeight);
      for (unsigned i = 0; i < embedded->mWidth * embedded->mHeight; ++i)
        t.rgb.insert(t.rgb.end(),
                     {embedded->pcData[i].r, embedded->pcData[i].g, embedded->pcData[i].b});
    }
  } else {
    std::vector<std::string> looked;
    if (auto found = find_texture(key, dir, paths, looked)) {
      out.files_read.push_back(*found);
      if (!load_image(*found, t, why)) why = found->string() + " cannot be decoded: " + why;
    } else {
      std::string list;
      for (const auto& l : looked) list += (list.empty() ? "" : ", ") + l;
      why = "not found (looked for " + list + ")";
    }
  }
  int index = -1;
  if (t.width > 0) {
    index = int(out.textures.size());
    out.textures.push_back(std::move(t));
  } else {
    aiString material;
    m->Get(AI_MATKEY_NAME, material);
    out.warnings.push_back(fmt::format(
        "texture '{}' of material '{}': {}; its surfaces take the material's colour instead", key,
        material.C_Str(), why.empty() ? "empty image" : why));
  }
  loaded[key] = index;
  return index;
}

// An OBJ's material libraries (`mtllib`) that are not there. Assimp goes on without them and
// says nothing the caller sees: the surfaces take the default colour. Like Assimp, a library is
// looked for beside the OBJ, then as the OBJ's own name with .mtl.
void check_material_libraries(const std::filesystem::path& path, Mesh& out) {
  namespace fs = std::filesystem;
  if (ascii_lower(path.extension().string()) != ".obj") return;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string row = trim(line);
    if (!row.starts_with("mtllib") || row.size() < 7 || (row[6] != ' ' && row[6] != '\t')) continue;
    const std::string library = trim(std::string_view(row).substr(7));
    if (library.empty()) continue;
    const std::string name = one_line(library);
    std::error_code ec;
    if (fs::is_regular_file(path.parent_path() / library, ec)) continue;
    fs::path fallback = path;
    fallback.replace_extension(".mtl");
    out.warnings.push_back(
        fs::is_regular_file(fallback, ec)
            ? fmt::format("{}:{}: material library '{}' not found; its materials are read from {}",
                          path.filename().string(), number, name, fallback.filename().string())
            : fmt::format("{}:{}: material library '{}' not found (nor {}); its surfaces take the "
                          "default colour",
                          path.filename().string(), number, name, fallback.filename().string()));
  }
}

}  // namespace

std::optional<UpAxis> parse_up_axis(const std::string& text) {
  std::string t = ascii_lower(text);
  int sign = 1;
  if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
    sign = t[0] == '-' ? -1 : 1;
    t.erase(0, 1);
  }
  if (t == "x") return UpAxis{0, sign};
  if (t == "y") return UpAxis{1, sign};
  if (t == "z") return UpAxis{2, sign};
  return std::nullopt;
}

std::string to_string(UpAxis up) {
  return std::string(up.sign < 0 ? "-" : "+") + "xyz"[up.axis];
}

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
// that fails there becomes an InputError here. The child exits without cleaning up (_exit); it
// is forked before any thread of the run's work starts (only the stop thread, which holds no lock
// the child takes), and stopped with the run.
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
  {
    const stop::ChildOnStop stopped_with_the_run(pid, false);
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
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

// Assimp's file system, noting every file a reader opens (an OBJ's material libraries, a glTF's
// buffers): outputs must not replace them.
class NotingIOSystem : public Assimp::DefaultIOSystem {
 public:
  explicit NotingIOSystem(std::vector<std::filesystem::path>& opened) : opened_(opened) {}
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    Assimp::IOStream* stream = DefaultIOSystem::Open(file, mode);
    if (stream) opened_.emplace_back(file);
    return stream;
  }

 private:
  std::vector<std::filesystem::path>& opened_;
};

Mesh read_mesh(const std::filesystem::path& path, const MeshOptions& options) {
  Mesh out;
  Assimp::Importer importer;
  importer.SetIOHandler(new NotingIOSystem(out.files_read));  // the importer owns it
  // An --up names an axis of the file as written: Assimp must not turn a Collada file first.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, options.up.has_value());
  // PreTransformVertices bakes every node's transform into its meshes: one frame for all.
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                           aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw InputError(path.string(), 0,
                     fmt::format("the mesh cannot be read: {}", importer.GetErrorString()));
  out.source = path.string();
  check_material_libraries(path, out);
  UpAxis up;
  if (options.up) {
    up = *options.up;
    out.up = to_string(up) + " (--up)";
  } else {
    std::tie(up, out.up) = declared_up(scene, path);
  }
  std::map<std::string, int> loaded;
  CaseInsensitivePaths paths;
  const bool names_materials = format_names_materials(path);
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    const aiMaterial* material = scene->mMaterials[m->mMaterialIndex];
    const Rgb base = material_color(material, options.default_color, names_materials);
    const bool vertex_colors = m->HasVertexColors(0);
    // Most specific first: a texture through UVs, then vertex colors, then the material's.
    const int texture =
        m->HasTextureCoords(0)
            ? material_texture(scene, material, path.parent_path(), out, loaded, paths)
            : -1;
    for (unsigned fi = 0; fi < m->mNumFaces; ++fi) {
      const aiFace& f = m->mFaces[fi];
      if (f.mNumIndices != 3) continue;  // points and lines carry no surface
      Triangle t;
      t.texture = texture;
      for (int k = 0; k < 3; ++k) {
        const unsigned vi = f.mIndices[k];
        // Assimp passes indices on as the file gives them (found by tools/fuzz.sh under ASan: a
        // PLY with more vertex lines than its header counts read a face's 139 in 3 vertices).
        if (vi >= m->mNumVertices)
          throw InputError(path.string(), 0,
                           fmt::format("a face names vertex {} of a mesh with {} vertices", vi,
                                       m->mNumVertices));
        if (texture >= 0) t.uv[k] = {m->mTextureCoords[0][vi].x, m->mTextureCoords[0][vi].y};
        t.v[k] = to_y_up(m->mVertices[vi], up);
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
