#include "ldraw/part_geometry.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "core/lattice.h"

namespace lego::ldraw {
namespace {

namespace fs = std::filesystem;

std::string base_name(const std::string& k) {
  auto slash = k.rfind('/');
  return slash == std::string::npos ? k : k.substr(slash + 1);
}

bool is_tube(const std::string& b) {
  return b.starts_with("stud3") || b.starts_with("stud4");
}
// Knobs: stud.dat, stud2.dat, stud2a.dat, stud10.dat, ... (stud3*/stud4* are underside tubes;
// stug* groups are expanded and their studs counted one by one).
bool is_knob(const std::string& b) {
  return b.starts_with("stud") && !is_tube(b);
}

class Walker {
 public:
  Walker(const PartSources& sources, PartGeometry& g) : sources_(sources), g_(g) {}

  bool walk_text(const std::string& text, const Transform& t, int depth, std::string& why) {
    if (depth > 32) {
      why = "part files nested too deeply";
      return false;
    }
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream s(line);
      int type = -1;
      if (!(s >> type)) continue;
      if (type == 0) {
        if (g_.title.empty() && depth == 0) {
          std::string rest;
          std::getline(s, rest);
          g_.title = rest.empty() ? ""
                                  : rest.substr(rest.find_first_not_of(' ') == std::string::npos
                                                    ? 0
                                                    : rest.find_first_not_of(' '));
        }
        continue;
      }
      std::string color;
      s >> color;
      if (type == 1) {
        Transform child;
        for (double& v : child.pos) s >> v;
        for (double& v : child.rot) s >> v;
        std::string name;
        std::getline(s, name);
        name.erase(0, name.find_first_not_of(" \t"));
        while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back())))
          name.pop_back();
        if (!s && name.empty()) continue;
        Transform world = t.then(child);
        std::string b = base_name(normalize_reference(name));
        if (is_knob(b)) {
          if (world.rot[4] > 0.5)
            g_.knobs.push_back(world.pos);
          else
            ++g_.upside_down_knobs;
          continue;
        }
        if (is_tube(b)) {
          ++g_.tubes;
          continue;
        }
        std::string sub;
        if (!load(name, sub)) continue;  // a missing primitive only loses some geometry
        if (!walk_text(sub, world, depth + 1, why)) return false;
        continue;
      }
      if (type >= 2 && type <= 4) {
        for (int v = 0; v < type; ++v) {
          double p[3];
          if (!(s >> p[0] >> p[1] >> p[2])) break;
          for (int a = 0; a < 3; ++a) {
            double w = t.pos[a];
            for (int k = 0; k < 3; ++k) w += t.rot[3 * a + k] * p[k];
            if (!any_) g_.min[a] = g_.max[a] = w;
            g_.min[a] = std::min(g_.min[a], w);
            g_.max[a] = std::max(g_.max[a], w);
          }
          any_ = true;
        }
      }
    }
    return true;
  }

  bool any() const { return any_; }

  bool load(const std::string& name, std::string& text) {
    std::string k = normalize_reference(name);
    if (sources_.embedded)
      for (const auto& [block, body] : *sources_.embedded)
        if (normalize_reference(block) == k ||
            base_name(normalize_reference(block)) == base_name(k)) {
          text = body;
          return true;
        }
    for (const auto& dir : sources_.library_dirs)
      for (const char* folder :
           {"p", "parts", "p/48", "parts/s", "unofficial/p", "unofficial/parts"})
        for (const std::string& candidate : {k, base_name(k)}) {
          fs::path path = dir / folder / candidate;
          std::ifstream in(path);
          if (!in) continue;
          std::ostringstream s;
          s << in.rdbuf();
          text = s.str();
          return true;
        }
    return false;
  }

 private:
  const PartSources& sources_;
  PartGeometry& g_;
  bool any_ = false;
};

}  // namespace

std::optional<PartGeometry> read_part_geometry(const PlacedPart& part, const PartSources& sources,
                                               std::string& why) {
  std::string text;
  if (!part.definition.empty()) {
    std::ifstream in(part.definition);
    if (!in) {
      why = "cannot read its part file " + part.definition.string();
      return std::nullopt;
    }
    std::ostringstream s;
    s << in.rdbuf();
    text = s.str();
  } else if (sources.embedded) {
    for (const auto& [block, body] : *sources.embedded)
      if (normalize_reference(block) == normalize_reference(part.embedded_definition)) text = body;
  }
  if (text.empty()) {
    why = "no part file for it";
    return std::nullopt;
  }
  PartGeometry g;
  Walker walker(sources, g);
  if (!walker.walk_text(text, Transform{}, 0, why)) return std::nullopt;
  if (!walker.any()) {
    why = "its part file draws nothing";
    return std::nullopt;
  }
  return g;
}

std::optional<BrickType> lattice_box_type(const std::string& part, const PartGeometry& g,
                                          const BrickCatalog& catalog, std::string& why) {
  constexpr double eps = 0.05;
  auto multiple = [&](double v, double unit) {
    return std::abs(v / unit - std::round(v / unit)) < eps / unit;
  };
  const double sx = g.max[0] - g.min[0], sy = g.max[1] - g.min[1], sz = g.max[2] - g.min[2];
  // The body (studs are primitives, not in the box): origin at the top centre, as LDraw parts are.
  if (std::abs(g.min[1]) > eps || std::abs(g.min[0] + g.max[0]) > eps ||
      std::abs(g.min[2] + g.max[2]) > eps || !multiple(sx, kLduPerStud) ||
      !multiple(sz, kLduPerStud) || !multiple(sy, kLduPerPlate) || sx < 1 || sz < 1 || sy < 1) {
    why = fmt::format("not a box on the lattice (body {:g} x {:g} x {:g} LDU)", sx, sy, sz);
    return std::nullopt;
  }
  const int length = int(std::round(sx / kLduPerStud)), width = int(std::round(sz / kLduPerStud));
  const int height = int(std::round(sy / kLduPerPlate));
  if (g.upside_down_knobs > 0) {
    why = "has knobs facing down";
    return std::nullopt;
  }
  std::set<std::pair<int, int>> cells;
  for (const auto& k : g.knobs) {
    double cx = (k[0] - g.min[0]) / kLduPerStud - 0.5, cz = (k[2] - g.min[2]) / kLduPerStud - 0.5;
    if (std::abs(k[1]) > eps || !multiple(cx, 1) || !multiple(cz, 1) || cx < -eps || cz < -eps ||
        cx > length - 1 + eps || cz > width - 1 + eps) {
      why = "has knobs off its top lattice (an offset or jumper part)";
      return std::nullopt;
    }
    cells.insert({int(std::round(cx)), int(std::round(cz))});
  }
  if (!cells.empty() && int(cells.size()) != length * width) {
    why = fmt::format("has {} knobs on a {} x {} top: only full or bare tops are analysed",
                      cells.size(), length, width);
    return std::nullopt;
  }
  // Mass: the mean density of the catalog's measured bricks, per stud² per plate.
  double mass = 0, volume = 0;
  for (const auto& t : catalog.types())
    if (t.mass_source.starts_with("paper")) {
      mass += t.mass_g;
      volume += double(t.length) * t.width * t.height;
    }
  if (volume <= 0) {
    why = "the catalog has no measured brick to estimate a mass from";
    return std::nullopt;
  }
  BrickType type;
  type.part = part;
  type.name = g.title;
  type.kind = cells.empty() ? "tile" : height % 3 == 0 ? "brick" : "plate";
  type.length = length;
  type.width = width;
  type.height = height;
  type.has_knobs = !cells.empty();
  type.mass_g = mass / volume * length * width * height;
  type.mass_source = fmt::format(
      "estimated from its volume at {:.4f} g per stud² per plate (the mean density of "
      "the paper's Table 1 bricks)",
      mass / volume);
  return type;
}

}  // namespace lego::ldraw
