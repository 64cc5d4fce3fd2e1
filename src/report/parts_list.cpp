#include "report/parts_list.h"

#include <fmt/format.h>

#include <fstream>
#include <set>

#include "core/brick_catalog.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/text.h"
#include "ldraw/color_table.h"

namespace lego::report {

std::vector<PartCount> count_parts(const Assembly& assembly) {
  std::map<std::pair<std::string, int>, PartCount> counts;
  for (const Brick& b : assembly.bricks) {
    PartCount& c = counts[{b.type->part, b.color}];
    c.part = b.type->part;
    c.color = b.color;
    c.name = readable_part_name(b.type->name);
    ++c.quantity;
  }
  std::vector<PartCount> out;
  for (auto& [key, c] : counts) out.push_back(c);
  return out;
}

std::string parts_list_csv(const std::vector<PartCount>& parts) {
  std::string out = "part,color,name,quantity\n";
  for (const PartCount& p : parts) {
    std::string name;  // CSV doubles quotes inside a quoted field
    for (char c : p.name) name += c == '"' ? std::string("\"\"") : std::string(1, c);
    out += fmt::format("{},{},\"{}\",{}\n", p.part, p.color, name, p.quantity);
  }
  return out;
}

BrickLinkMap BrickLinkMap::load(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  if (!in) throw InputError(csv.string(), 0, "cannot read the BrickLink map");
  BrickLinkMap map;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> f = split_csv(line);
    if (f.size() < 3) throw InputError(csv.string(), n, "expected kind,ldraw,bricklink[,name]");
    if (f[0] == "part") {
      map.items_[f[1]] = f[2];
    } else if (f[0] == "color") {
      try {
        map.colors_[std::stoi(f[1])] = std::stoi(f[2]);
      } catch (const std::exception&) {
        throw InputError(csv.string(), n, "color codes must be numbers");
      }
    } else {
      throw InputError(csv.string(), n, "unknown kind '" + f[0] + "' (part or color)");
    }
  }
  return map;
}

const BrickLinkMap& BrickLinkMap::standard() {
  static const BrickLinkMap map = load(default_parts_dir() / "bricklink.csv");
  return map;
}

const std::string* BrickLinkMap::item(const std::string& part) const {
  auto it = items_.find(part);
  return it == items_.end() ? nullptr : &it->second;
}

const int* BrickLinkMap::color(int code) const {
  auto it = colors_.find(code);
  return it == colors_.end() ? nullptr : &it->second;
}

std::string bricklink_xml(const std::vector<PartCount>& parts, const BrickLinkMap& map) {
  std::string missing;
  std::set<int> colors_told;  // each colour once, not once per part that has it
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<INVENTORY>\n";
  for (const PartCount& p : parts) {
    const std::string* item = map.item(p.part);
    const int* color = map.color(p.color);
    if (!item)
      missing += fmt::format("\n  part {} ({}) has no BrickLink item number", p.part, p.name);
    if (!color && colors_told.insert(p.color).second)
      missing += fmt::format("\n  LDraw color {} ({}) has no BrickLink color", p.color,
                             ldraw::ColorTable::standard().name(p.color));
    if (!item || !color) continue;
    out += fmt::format(
        "  <ITEM>\n    <ITEMTYPE>P</ITEMTYPE>\n    <ITEMID>{}</ITEMID>\n    <COLOR>{}</COLOR>\n"
        "    <MINQTY>{}</MINQTY>\n  </ITEM>\n",
        *item, *color, p.quantity);
  }
  if (!missing.empty())
    throw InputError(
        "", 0, "no BrickLink wanted list: the map (ldraw_parts/bricklink.csv) lacks" + missing);
  return out + "</INVENTORY>\n";
}

}  // namespace lego::report
