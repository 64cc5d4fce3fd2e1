#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/assembly.h"
#include "core/brick_catalog.h"
#include "ldraw/reader.h"

namespace lego::ldraw {

// A placed part that did not become a brick, and why.
struct SkippedPart {
  size_t part = 0;  // index into Model::parts
  std::string reason;
};

struct AssemblyConversion {
  Assembly assembly;
  std::vector<size_t> brick_part;  // for each brick, its index into Model::parts
  std::vector<SkippedPart> skipped;
  // Types learnt from part files (LDraw library or embedded in the MPD): bricks point into it.
  std::unique_ptr<BrickCatalog> learnt = std::make_unique<BrickCatalog>();
};

// Catalog parts on the lattice with a yaw of 0/90/180/270 degrees become bricks. A part outside
// the catalog whose definition we have (an embedded FILE, or a file found in `library_dirs` or
// next to the model) becomes one too when it is a lattice box (part_geometry.h). Anything else
// (an unknown part, one off the lattice, tilted or upside down) is listed with the reason.
// The lattice phase is the one most parts agree on, so a model drawn around any origin works.
AssemblyConversion to_assembly(const Model& model, const BrickCatalog& catalog,
                               const std::vector<std::filesystem::path>& library_dirs = {});

// The LDraw transform of a brick of an assembly (origin at the top centre of its body).
Transform brick_transform(const Brick& brick, const std::array<int, 3>& origin_ldu);

}  // namespace lego::ldraw
