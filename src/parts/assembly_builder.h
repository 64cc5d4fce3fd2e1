#pragma once
// A read LDraw model as an Assembly: every placed part analysed as structure (a brick with its
// exact pose), carried (PHYSICS.md "Carried parts"), or left out because nothing is known of it.
#include <memory>
#include <string>
#include <vector>

#include "core/assembly.h"
#include "core/brick_catalog.h"
#include "ldraw/reader.h"
#include "parts/part_library.h"

namespace lego::parts {

// A placed part left out of the analysis: nothing of it is known (a part no library holds, a
// submodel no file holds), or it is a copy of another part in the same place, which is not there.
struct PartNote {
  size_t part = 0;  // index into Model::parts
  PartRole role = PartRole::UnknownPart;
  std::string reason;  // as the reports say it, with the files it names
};

struct AssemblyConversion {
  Assembly assembly;
  std::vector<size_t> brick_part;              // per brick: its index into Model::parts
  std::vector<size_t> carried_part;            // per carried part: its index into Model::parts
  std::vector<PartNote> skipped;               // left out: nothing is known of them
  std::vector<ldraw::Diagnostic> diagnostics;  // matrices made orthonormal, and the like
  // Where the model's plates lie, in its frame: the height (LDU, in [0, 8)) modulo a plate that
  // most upright parts' origins share. Parts are placed as drawn; report/drawn_by_eye.h takes
  // those drawn a little off this onto it.
  double plates = 0;
  // The kinds of part the bricks point into (PartLibrary keeps their knowledge).
  std::unique_ptr<BrickCatalog> types = std::make_unique<BrickCatalog>();
};

// `fixed_parts`: indices into Model::parts the user names as fixed (--ground-part).
// `budget`: stops with OutOfTime when spent.
AssemblyConversion to_assembly(const ldraw::Model& model, PartLibrary& library,
                               const std::vector<size_t>& fixed_parts = {},
                               const Budget* budget = nullptr);

// A rotation within `tolerance` of an orthonormal one, made exactly so; nullopt when it is scaled
// or sheared beyond that.
std::optional<std::array<double, 9>> orthonormalized(const std::array<double, 9>& rotation,
                                                     double tolerance);
// The signed permutation within `tolerance` of an orthonormal rotation, or nullopt.
std::optional<std::array<double, 9>> quarter_turn(const std::array<double, 9>& rotation,
                                                  double tolerance);

}  // namespace lego::parts
