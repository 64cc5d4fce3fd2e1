#include "ldraw/assembly_builder.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "core/lattice.h"
#include "ldraw/part_geometry.h"

namespace lego::ldraw {
namespace {

constexpr double kTolerance = 1e-3;  // LDU and matrix entries

bool near(double a, double b) {
  return std::abs(a - b) < kTolerance;
}

std::optional<long> integral(double v) {
  double r = std::round(v);
  if (!near(v, r)) return std::nullopt;
  return long(r);
}

long positive_mod(long v, long m) {
  return ((v % m) + m) % m;
}

// Footprint corner and orientation of a catalog part, in LDU, before the lattice check.
struct Candidate {
  size_t part = 0;
  const BrickType* type = nullptr;
  bool rotated = false;
  double x_min = 0, z_min = 0, y_bottom = 0;  // LDraw y of the bottom face (down is +)
};

// Why a placement is not a yaw about the vertical, or empty when it is.
std::string orientation_problem(const Transform& t) {
  const auto& m = t.rot;
  if (!t.orthonormal(kTolerance)) return "scaled or sheared";
  if (near(m[4], -1)) return "upside down";
  if (!near(m[4], 1) || !near(m[1], 0) || !near(m[3], 0) || !near(m[5], 0) || !near(m[7], 0))
    return "tilted (not upright)";
  for (int i : {0, 2, 6, 8})
    if (!near(m[i], 0) && !near(std::abs(m[i]), 1))
      return "turned by an angle that is not a multiple of 90 degrees";
  return {};
}

}  // namespace

AssemblyConversion to_assembly(const Model& model, const BrickCatalog& catalog,
                               const std::vector<std::filesystem::path>& library_dirs) {
  AssemblyConversion out;
  std::vector<Candidate> candidates;
  std::map<std::string, std::string> not_a_brick;  // part -> why, analysed once per part
  const PartSources sources{library_dirs, &model.embedded_parts};
  auto type_of = [&](const PlacedPart& p, std::string& why) -> const BrickType* {
    if (const BrickType* t = catalog.find(p.part)) return t;
    if (const BrickType* t = out.learnt->find(p.part)) return t;
    if (auto it = not_a_brick.find(p.part); it != not_a_brick.end()) {
      why = it->second;
      return nullptr;
    }
    if (p.definition.empty() && p.embedded_definition.empty()) {
      why = "unknown part (not in the brick catalog; no part file found, see --ldraw-dir)";
    } else if (auto g = read_part_geometry(p, sources, why)) {
      if (auto type = lattice_box_type(p.part, *g, catalog, why))
        return &out.learnt->add(std::move(*type));
      why = "not analysable: " + why;
    } else {
      why = "not analysable: " + why;
    }
    not_a_brick[p.part] = why;
    return nullptr;
  };
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const PlacedPart& p = model.parts[i];
    std::string why;
    const BrickType* type = type_of(p, why);
    if (!type) {
      out.skipped.push_back({i, why});
      continue;
    }
    if (auto problem = orientation_problem(p.transform); !problem.empty()) {
      out.skipped.push_back({i, problem});
      continue;
    }
    Candidate c{i, type, std::abs(p.transform.rot[0]) < 0.5};
    double ext_x = kLduPerStud * (c.rotated ? type->width : type->length);
    double ext_z = kLduPerStud * (c.rotated ? type->length : type->width);
    c.x_min = p.transform.pos[0] - ext_x / 2;
    c.z_min = p.transform.pos[2] - ext_z / 2;
    c.y_bottom = p.transform.pos[1] + kLduPerPlate * type->height;
    candidates.push_back(c);
  }
  // The lattice phase: the residue most parts share on each axis.
  std::map<long, int> votes[3];
  for (const auto& c : candidates) {
    auto x = integral(c.x_min), y = integral(c.y_bottom), z = integral(c.z_min);
    if (x && y && z) {
      ++votes[0][positive_mod(*x, kLduPerStud)];
      ++votes[1][positive_mod(*y, kLduPerPlate)];
      ++votes[2][positive_mod(*z, kLduPerStud)];
    }
  }
  long phase[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    int best = 0;
    for (auto [residue, count] : votes[a])
      if (count > best) best = count, phase[a] = residue;
  }
  out.assembly.origin_ldu = {int(phase[0]), int(phase[1]), int(phase[2])};
  for (const auto& c : candidates) {
    const PlacedPart& p = model.parts[c.part];
    auto x = integral(c.x_min), y = integral(c.y_bottom), z = integral(c.z_min);
    if (!x || !y || !z || positive_mod(*x, kLduPerStud) != phase[0] ||
        positive_mod(*z, kLduPerStud) != phase[2] || positive_mod(*y, kLduPerPlate) != phase[1]) {
      out.skipped.push_back(
          {c.part, fmt::format("off the lattice (at {:g} {:g} {:g} LDU)", p.transform.pos[0],
                               p.transform.pos[1], p.transform.pos[2])});
      continue;
    }
    Brick b;
    b.type = c.type;
    b.rotated = c.rotated;
    b.min = {int((*x - phase[0]) / kLduPerStud), int((phase[1] - *y) / kLduPerPlate),
             int((*z - phase[2]) / kLduPerStud)};
    b.color = p.color;
    b.source = {p.file, p.line, p.step};
    out.assembly.bricks.push_back(b);
    out.brick_part.push_back(c.part);
  }
  // The ground is the lowest face of the whole model. A left-out part whose origin (by LDraw
  // convention the top of a part) is at or below the bottom of every analysed brick reaches at
  // least a plate lower: the analysed bricks then stand on parts we could not analyse, not on
  // the ground.
  if (!out.assembly.bricks.empty()) {
    const int lowest = out.assembly.ground_level();
    double ground = lowest;
    for (const auto& s : out.skipped) {
      double top =
          std::floor((phase[1] - model.parts[s.part].transform.pos[1]) / kLduPerPlate + 1e-6);
      if (top <= lowest) ground = std::min(ground, top - 1);
    }
    if (ground < lowest) out.assembly.ground_y = int(ground);
  }
  std::sort(out.skipped.begin(), out.skipped.end(),
            [](const SkippedPart& a, const SkippedPart& b) { return a.part < b.part; });
  return out;
}

Transform brick_transform(const Brick& brick, const std::array<int, 3>& origin_ldu) {
  Transform t;
  t.pos[0] = origin_ldu[0] + kLduPerStud * brick.min.x + kLduPerStud * brick.size_x() / 2.0;
  t.pos[2] = origin_ldu[2] + kLduPerStud * brick.min.z + kLduPerStud * brick.size_z() / 2.0;
  t.pos[1] = origin_ldu[1] - kLduPerPlate * (brick.min.y + brick.height());
  if (brick.rotated) t.rot = {0, 0, 1, 0, 1, 0, -1, 0, 0};
  return t;
}

}  // namespace lego::ldraw
