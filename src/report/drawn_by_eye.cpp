#include "report/drawn_by_eye.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "core/lattice.h"

namespace lego::report {
namespace {

bool upright(const Brick& b) {
  return std::abs(std::abs(b.pose->rotation[4]) - 1) < 1e-9;
}

// The shift (LDU) that brings `v` onto the grid of `pitch` through `at`, when it is at most
// `reach`; else zero.
double shift_within(double v, double at, double pitch, double reach) {
  const double shift = onto_grid(v, at, pitch);
  return std::abs(shift) <= reach + 1e-6 ? shift : 0.0;
}

}  // namespace

void take_onto_the_plates(parts::AssemblyConversion& conversion) {
  // One LDU and no farther; a part closer than this to its plates is on them.
  constexpr double kPlateSlip = 1.0, kOnPlates = 1e-3;
  for (Brick& b : conversion.assembly.bricks) {
    // The slip brings studs onto the plates: a part with none, held on lines by pins, bars or
    // clips (an exhaust pipe in a headlight brick's hole), stays where it is drawn.
    const PartShape& shape = b.type->shape;
    if (!b.pose || b.frame || !upright(b) || (shape.studs.empty() && shape.receptacles.empty()))
      continue;
    const double slip =
        shift_within(b.pose->origin[1], conversion.plates, kLduPerPlate, kPlateSlip);
    if (std::abs(slip) <= kOnPlates) continue;
    b.pose->origin[1] += slip;
    conversion.diagnostics.push_back(
        {ldraw::Severity::Warning, b.source.file, b.source.line,
         fmt::format("placed {:g} LDU {} the plates the model's other parts stand on: taken as "
                     "on them",
                     std::abs(slip), slip > 0 ? "above" : "below")});
  }
}

// Beyond the editor's nudge, and across, a part beside the lattice may be a SNOT assembly offset
// on purpose, which holds together as drawn. So only parts whose studs and receptacles meet nothing
// that stands (`floating`) are moved onto the lattice, and only those that then meet what stands
// stay moved, each with a warning naming its line. Across, as far as a stud stays inside its
// receptacle's cell (kStudInCellLdu); up and down, upright parts as far as half a stud's height:
// drawn 2 LDU above its plates (the bait shop's roof) a part still sits on the studs' upper half,
// drawn below it would cut into the part under it. Returns whether any did.
bool nudge_onto_the_lattice(parts::AssemblyConversion& conversion,
                            const std::vector<char>& floating, const FloatingBricks& floating_now) {
  Assembly& a = conversion.assembly;
  constexpr double kHalfStudHeight = 2.0;
  // The lattice: the residue (hundredths of an LDU) most parts share, across modulo half a stud,
  // up modulo a plate.
  constexpr double kGrid = kLduPerStud / 2;
  std::map<std::pair<long, long>, int> votes;
  std::map<long, int> heights;
  for (const Brick& b : a.bricks)
    if (b.pose && !b.frame) {
      ++votes[{residue_hundredths(b.pose->origin[0], kGrid),
               residue_hundredths(b.pose->origin[2], kGrid)}];
      if (upright(b)) ++heights[residue_hundredths(b.pose->origin[1], kLduPerPlate)];
    }
  if (votes.empty()) return false;
  auto most = [](const auto& x, const auto& y) { return x.second < y.second; };
  const auto grid = std::max_element(votes.begin(), votes.end(), most)->first;
  const long plates =
      heights.empty() ? 0 : std::max_element(heights.begin(), heights.end(), most)->first;
  std::vector<std::pair<int, Vec3>> moved;  // brick, its origin as drawn
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    Brick& b = a.bricks[i];
    if (!floating[i] || !b.pose || b.frame) continue;
    const Vec3 shift{
        shift_within(b.pose->origin[0], double(grid.first) / 100, kGrid, kStudInCellLdu),
        upright(b)
            ? shift_within(b.pose->origin[1], double(plates) / 100, kLduPerPlate, kHalfStudHeight)
            : 0.0,
        shift_within(b.pose->origin[2], double(grid.second) / 100, kGrid, kStudInCellLdu)};
    if (std::max({std::abs(shift[0]), std::abs(shift[1]), std::abs(shift[2])}) < 1e-3) continue;
    moved.emplace_back(int(i), b.pose->origin);
    for (int k = 0; k < 3; ++k) b.pose->origin[size_t(k)] += shift[size_t(k)];
  }
  if (moved.empty()) return false;
  const std::vector<char> still = floating_now(a);
  bool any = false;
  for (const auto& [i, drawn] : moved) {
    Brick& b = a.bricks[size_t(i)];
    if (still[size_t(i)]) {
      b.pose->origin = drawn;
      continue;
    }
    any = true;
    const double across =
        std::max(std::abs(b.pose->origin[0] - drawn[0]), std::abs(b.pose->origin[2] - drawn[2]));
    const double below = drawn[1] - b.pose->origin[1];  // LDraw's y points down
    const bool beside = across > 1e-3, off_plates = std::abs(below) > 1e-3;
    std::string where;
    if (beside) where = fmt::format("{:g} LDU beside the lattice", across);
    if (off_plates)
      where += fmt::format("{}{:g} LDU {} the plates", beside ? " and " : "", std::abs(below),
                           below > 0 ? "below" : "above");
    conversion.diagnostics.push_back(
        {ldraw::Severity::Warning, b.source.file, b.source.line,
         fmt::format("placed {} the model's other parts {}, its studs meeting nothing: taken as "
                     "on {}, where they meet what stands",
                     where, beside ? "share" : "stand on", off_plates ? "them" : "it")});
  }
  return any;
}

}  // namespace lego::report
