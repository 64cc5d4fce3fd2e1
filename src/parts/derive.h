#pragma once
// What a part is, derived from its flattened geometry (PHYSICS.md "Parts"): its body as boxes,
// its studs, its receptacles, its mass and where that comes from, whether it is a baseplate, and
// whether its connections can be modelled at all.
#include <optional>
#include <string>

#include "core/brick_catalog.h"
#include "core/part_role.h"
#include "parts/part_geometry.h"

namespace lego::parts {

struct PartKnowledge {
  BrickType type;                   // name, shape, mass and its source, baseplate
  std::optional<PartRole> carried;  // none: analysed as structure; else why it is carried
};

// `part` is the catalog's name for it ("3001", "s/3068bs01"); the catalog gives the masses it
// knows (paper Table 1); any other mass is estimated from the body's volume, and says so.
PartKnowledge derive_part(const std::string& part, const PartGeometry& geometry,
                          const BrickCatalog& catalog);

// The body of the geometry: for each column one stud across (around the cell centred at
// `cell_centre` and its neighbours, or from the part's side), the extent of its faces along y,
// merged into boxes.
std::vector<Box> body_boxes(const PartGeometry& geometry, const std::optional<Vec3>& cell_centre);

// Where a stud fits into the part from below: nothing of the part within a stud's size above the
// point, and the part around it. The cells share one lattice; bores are the tubes' insides, on
// the lattice half a stud off it both ways.
struct Receptacles {
  std::vector<Connector> cells, bores;
};
Receptacles receptacles(const PartGeometry& geometry);

// The geometry's farthest points in 124 directions (PartShape::outline).
std::vector<Vec3> outline(const PartGeometry& geometry);

// Grams per LDU³ of the paper's measured bricks (their mean density, bricks being hollow boxes).
double estimated_density(const BrickCatalog& catalog);

}  // namespace lego::parts
