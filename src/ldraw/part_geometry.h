#pragma once
// What an LDraw part file tells about a part beyond our catalog: its knobs (stud primitives),
// tubes, and the bounding box of its body, and whether that makes it a box on the lattice the
// physics can treat like a catalog brick.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/brick_catalog.h"
#include "ldraw/reader.h"

namespace lego::ldraw {

struct PartGeometry {
  double min[3] = {0, 0, 0}, max[3] = {0, 0, 0};  // body bounding box (LDU, studs excluded)
  std::vector<std::array<double, 3>> knobs;       // stud origins (base centre), upright only
  int tubes = 0;                                  // stud3*/stud4* underside primitives
  int upside_down_knobs = 0;
  std::string title;
};

// Where subfiles of a part are looked up: the LDraw libraries and the MPD's embedded blocks.
struct PartSources {
  std::vector<std::filesystem::path> library_dirs;
  const std::vector<std::pair<std::string, std::string>>* embedded = nullptr;
};

// Reads a part definition (a file on disk, or the text of an embedded block) and its subfiles.
// Returns nullopt with `why` set when it cannot be read.
std::optional<PartGeometry> read_part_geometry(const PlacedPart& part, const PartSources& sources,
                                               std::string& why);

// A BrickType for a part that is an upright box on the lattice with a knob on every top cell
// or none (a tile), or nullopt with the reason it is not. The mass comes from the body's volume
// at the mean density of the catalog's measured bricks.
std::optional<BrickType> lattice_box_type(const std::string& part, const PartGeometry& g,
                                          const BrickCatalog& catalog, std::string& why);

}  // namespace lego::ldraw
