#pragma once
#include <deque>
#include <filesystem>
#include <string>
#include <string_view>
#include <unordered_map>

#include "core/part_shape.h"

namespace lego {

// One kind of part the physics understands. The catalog's bricks and plates are boxes on the
// lattice with knobs on top; parts learnt from an LDraw library (src/parts/) have any shape.
struct BrickType {
  std::string part;  // LDraw part number without ".dat", lower case ("3001")
  std::string name;  // "Brick  2 x  4"
  std::string kind;  // "brick", "plate", or what the source says
  int length = 1;    // studs along the part's local x axis (length >= width)
  int width = 1;     // studs along the part's local z axis
  int height = 3;    // plates
  double mass_g = 0;
  std::string mass_source;
  bool has_knobs = true;
  PartShape shape;         // empty body: the box of length x width x height (box_brick_shape)
  bool baseplate = false;  // the library says so: at the bottom of a model it is the ground
  bool pivots = false;     // a hinge or turntable half: it turns on its other half
  // A wheel or a tyre with its axle line: round about it, it meets a table along a strip.
  bool rolls = false;
};

// The parts we support, read from ldraw_parts/catalog.csv. Types have stable addresses, so
// bricks can point at them for as long as the catalog lives.
class BrickCatalog {
 public:
  static BrickCatalog load(const std::filesystem::path& csv_file);
  // The catalog in the parts directory found by default_parts_dir().
  static const BrickCatalog& standard();

  const BrickType* find(std::string_view part) const;  // accepts "3001", "3001.dat", "3001.DAT"
  // The catalog type with this footprint and height (length >= width), or nullptr.
  const BrickType* find_by_size(int length, int width, int height) const;
  // For parts learnt from an LDraw library; a type without a body gets the box of its size.
  const BrickType& add(BrickType type);
  const std::deque<BrickType>& types() const { return types_; }

 private:
  std::deque<BrickType> types_;
  std::unordered_map<std::string, const BrickType*> by_part_;
};

// ldraw_parts/: $LEGOLIZATION_PARTS if set, else the folder this build was configured with.
std::filesystem::path default_parts_dir();

// How LDraw names files: case-insensitively, with either slash. "S\\3068bs01.DAT" ->
// "s/3068bs01.dat".
std::string normalize_reference(std::string_view name);

// A part number as the catalog knows it: "parts/3001.DAT" -> "3001"; "s\\3068bs01.dat" ->
// "s/3068bs01".
std::string normalize_part_name(std::string_view name);

}  // namespace lego
