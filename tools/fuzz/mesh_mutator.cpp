#include "mesh_mutator.h"

#include <fmt/format.h>

#include <array>
#include <vector>

namespace lego::fuzz {
namespace {

bool chance(Rng& rng, double p) {
  return std::uniform_real_distribution<double>(0, 1)(rng) < p;
}

struct Shape {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> triangles;  // 0-based
  std::vector<std::array<int, 3>> colours;    // per vertex, 0-255
};

// A box, a tetrahedron or a sliver, at a random size: 1e-3 to 3e9 units.
Shape shape(Rng& rng) {
  Shape s;
  static const double kSizes[] = {1e-3, 1, 10, 100, 1000, 3e9};
  const double size = kSizes[rng() % 6];
  switch (rng() % 3) {
    case 0:
      for (int k = 0; k < 8; ++k)
        s.vertices.push_back({size * (k & 1), size * ((k >> 1) & 1), size * ((k >> 2) & 1)});
      s.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
      break;
    case 1:
      s.vertices = {{0, 0, 0}, {size, 0, 0}, {0, size, 0}, {0, 0, size}};
      s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
      break;
    default:  // a sliver: long and nearly flat
      s.vertices = {{0, 0, 0}, {size, 0, 0}, {0, size * 1e-6, 0}};
      s.triangles = {{0, 1, 2}};
  }
  for (size_t k = 0; k < s.vertices.size(); ++k)
    s.colours.push_back({int(rng() % 256), int(rng() % 256), int(rng() % 256)});
  return s;
}

std::string obj(const Shape& s, bool colours, bool material) {
  std::string out = material ? "mtllib mesh.mtl\nusemtl red\n" : "";
  for (size_t k = 0; k < s.vertices.size(); ++k) {
    const auto& v = s.vertices[k];
    out += fmt::format("v {} {} {}", v[0], v[1], v[2]);
    if (colours)
      out += fmt::format(" {} {} {}", s.colours[k][0] / 255.0, s.colours[k][1] / 255.0,
                         s.colours[k][2] / 255.0);
    out += '\n';
  }
  for (const auto& t : s.triangles)
    out += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  return out;
}

std::string ply(const Shape& s) {
  std::string out = fmt::format(
      "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
      s.vertices.size(), s.triangles.size());
  for (size_t k = 0; k < s.vertices.size(); ++k) {
    const auto& v = s.vertices[k];
    out += fmt::format("{} {} {} {} {} {}\n", v[0], v[1], v[2], s.colours[k][0], s.colours[k][1],
                       s.colours[k][2]);
  }
  for (const auto& t : s.triangles) out += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
  return out;
}

std::string stl(const Shape& s) {
  std::string out = "solid fuzz\n";
  for (const auto& t : s.triangles) {
    out += "facet normal 0 0 0\nouter loop\n";
    for (int k : t) {
      const auto& v = s.vertices[size_t(k)];
      out += fmt::format("vertex {} {} {}\n", v[0], v[1], v[2]);
    }
    out += "endloop\nendfacet\n";
  }
  return out + "endsolid fuzz\n";
}

// Positions of the numbers in the text (start, length).
std::vector<std::pair<size_t, size_t>> numbers(const std::string& text) {
  std::vector<std::pair<size_t, size_t>> out;
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if ((c >= '0' && c <= '9') || c == '-' || c == '.') {
      size_t j = i;
      while (j < text.size() && text[j] != ' ' && text[j] != '\n') ++j;
      out.emplace_back(i, j - i);
      i = j;
    } else {
      ++i;
    }
  }
  return out;
}

std::string damage(std::string text, Rng& rng) {
  static const char* kNumbers[] = {"nan",    "inf", "-inf",       "1e308",       "1e999",
                                   "3e9",    "-1",  "2147483648", "99999999999", "0",
                                   "1e-320", "",    "x",          "-0"};
  for (int e = 0, edits = 1 + int(rng() % 4); e < edits; ++e) {
    switch (rng() % 5) {
      case 0:
      case 1: {  // a number (a coordinate, an index, a count in a header) replaced
        auto n = numbers(text);
        if (n.empty()) break;
        const auto [at, length] = n[rng() % n.size()];
        text.replace(at, length, kNumbers[rng() % (sizeof kNumbers / sizeof kNumbers[0])]);
        break;
      }
      case 2: {  // a line duplicated or removed
        const size_t at = text.empty() ? 0 : rng() % text.size();
        const size_t start =
            text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
        const size_t end =
            text.find('\n', at) == std::string::npos ? text.size() : text.find('\n', at) + 1;
        const std::string line = text.substr(start, end - start);
        if (chance(rng, 0.5))
          text.erase(start, end - start);
        else
          text.insert(start, chance(rng, 0.05) ? std::string() : line + line);
        break;
      }
      case 3:  // cut
        text.resize(text.empty() ? 0 : rng() % text.size());
        break;
      default:  // bytes
        if (!text.empty()) text[rng() % text.size()] = char(rng() % 256);
    }
  }
  return text;
}

}  // namespace

const char* name(MeshFormat format) {
  static const char* names[kMeshFormats] = {"obj", "ply", "stl"};
  return names[int(format)];
}

MeshFile mutated_mesh(MeshFormat format, Rng& rng) {
  const Shape s = shape(rng);
  MeshFile file;
  switch (format) {
    case MeshFormat::Obj: {
      const bool material = chance(rng, 0.5);
      file.extension = ".obj";
      file.text = obj(s, chance(rng, 0.5), material);
      if (material)
        file.mtl = chance(rng, 0.5) ? damage("newmtl red\nKd 0.8 0.1 0.1\nmap_Kd tex.png\n", rng)
                                    : "newmtl red\nKd 0.8 0.1 0.1\n";
      break;
    }
    case MeshFormat::Ply:
      file.extension = ".ply";
      file.text = ply(s);
      break;
    case MeshFormat::Stl:
      file.extension = ".stl";
      file.text = stl(s);
  }
  // Now and then the mesh is left whole: the driver then also runs a valid file through.
  if (!chance(rng, 0.1)) file.text = damage(file.text, rng);
  return file;
}

}  // namespace lego::fuzz
