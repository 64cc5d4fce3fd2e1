#pragma once
// What to buy: the bricks of an assembly counted by part and color, as a CSV parts list and as a
// BrickLink XML wanted list.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/assembly.h"

namespace lego::report {

struct PartCount {
  std::string part;  // LDraw part number
  int color = 16;    // LDraw color code
  std::string name;
  int quantity = 0;
};

// By part, then color; each (part, color) once.
std::vector<PartCount> count_parts(const Assembly& assembly);

// "part,color,name,quantity" with a header line; names quoted.
std::string parts_list_csv(const std::vector<PartCount>& parts);

// BrickLink item numbers and color ids for LDraw parts and codes (ldraw_parts/bricklink.csv).
class BrickLinkMap {
 public:
  static BrickLinkMap load(const std::filesystem::path& csv);  // throws InputError with file:line
  static const BrickLinkMap& standard();                       // from default_parts_dir()
  const std::string* item(const std::string& part) const;
  const int* color(int ldraw_code) const;

 private:
  std::map<std::string, std::string> items_;
  std::map<int, int> colors_;
};

// A BrickLink wanted list (<INVENTORY><ITEM>...). Throws InputError naming every part or color
// the map lacks: a wrong color on an order is worse than no list.
std::string bricklink_xml(const std::vector<PartCount>& parts, const BrickLinkMap& map);

}  // namespace lego::report
