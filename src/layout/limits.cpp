#include "layout/limits.h"

#include <charconv>
#include <cstdint>
#include <fstream>

#include "core/csv.h"
#include "core/error.h"
#include "core/lattice.h"
#include "core/text.h"
#include "ldraw/color_table.h"

namespace lego::layout {

namespace {

bool parse_int(std::string_view s, int& out) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size();
}

// "2x4", "4x2" or a brick part number -> (length, width).
std::pair<int, int> parse_size(const std::string& what, const BrickCatalog& catalog,
                               const std::string& file, int line) {
  if (auto x = what.find_first_of("xX"); x != std::string::npos) {
    int a = 0, b = 0;
    if (parse_int(what.substr(0, x), a) && parse_int(what.substr(x + 1), b) && a > 0 && b > 0)
      return {std::max(a, b), std::min(a, b)};
  }
  const BrickType* type = catalog.find(what);
  if (!type)
    throw InputError(file, line,
                     "'" + what + "' is neither a size like 2x4 nor a part in the catalog");
  if (type->height != kPlatesPerBrick)
    throw InputError(file, line,
                     "part " + type->part + " (" + readable_part_name(type->name) +
                         ") is not a brick: layouts are built of bricks only");
  return {type->length, type->width};
}

int parse_color(const std::string& what, const std::string& file, int line) {
  auto code = ldraw::parse_color_code(what);
  if (!code) throw InputError(file, line, "'" + what + "' is not an LDraw color code");
  return *code;
}

int parse_count(const std::string& what, const std::string& file, int line) {
  int n = 0;
  if (!parse_int(what, n) || n < 0)
    throw InputError(file, line, "'" + what + "' is not a count (a whole number >= 0)");
  return n;
}

}  // namespace

bool Limits::limits_size(int length, int width) const {
  if (listed_only || by_size.contains({length, width})) return true;
  auto it = by_size_color.lower_bound({length, width, INT32_MIN});
  return it != by_size_color.end() && std::get<0>(it->first) == length &&
         std::get<1>(it->first) == width;
}

int Limits::stand_ins(const Layout& layout, int length, int width, int color) const {
  return (color == inside_color ? layout.count(length, width, kIgnore) : 0) +
         (color == support_color ? layout.count(length, width, kSupport) : 0);
}

bool Limits::allow(const Layout& layout, const LayoutBrick& b) const {
  if (empty() && !listed_only) return true;
  const int l = b.length(), w = b.width();
  const int color = ldraw_color(b.color, inside_color, support_color);
  auto size = by_size.find({l, w});
  if (size != by_size.end() && layout.count(l, w) + 1 > size->second) return false;
  auto colored = by_size_color.find({l, w, color});
  if (colored != by_size_color.end()) {
    int used = layout.count(l, w, color);
    used += stand_ins(layout, l, w, color);
    return used + 1 <= colored->second;
  }
  return !listed_only || size != by_size.end();
}

std::vector<std::string> Limits::exceeded(const Layout& layout) const {
  std::vector<std::string> out;
  for (auto& [size, limit] : by_size)
    if (int used = layout.count(size.first, size.second); used > limit)
      out.push_back(std::to_string(size.second) + "x" + std::to_string(size.first) + ": " +
                    std::to_string(used) + " used, limit " + std::to_string(limit));
  std::map<std::tuple<int, int, int>, int> used;
  for (int id : layout.brick_ids()) {
    const LayoutBrick& b = layout.brick(id);
    ++used[{b.length(), b.width(), ldraw_color(b.color, inside_color, support_color)}];
  }
  for (auto& [key, n] : used) {
    auto [l, w, color] = key;
    auto limit = by_size_color.find(key);
    const bool unlisted = limit == by_size_color.end() && !by_size.contains({l, w});
    if ((limit != by_size_color.end() && n > limit->second) || (listed_only && unlisted))
      out.push_back(std::to_string(w) + "x" + std::to_string(l) + " in color " +
                    std::to_string(color) + ": " + std::to_string(n) + " used, limit " +
                    std::to_string(limit == by_size_color.end() ? 0 : limit->second));
  }
  return out;
}

void Limits::use_up(const Layout& layout) {
  for (auto& [size, limit] : by_size)
    limit = std::max(0, limit - layout.count(size.first, size.second));
  for (auto& [key, limit] : by_size_color) {
    const auto [l, w, color] = key;
    int used = layout.count(l, w, color);
    used += stand_ins(layout, l, w, color);
    limit = std::max(0, limit - used);
  }
}

void Limits::add(std::string_view spec_view, const BrickCatalog& catalog, std::string_view origin) {
  const std::string spec = trim(spec_view), where(origin);
  const auto colon = spec.rfind(':');
  if (colon == std::string::npos)
    throw InputError(where, 0, "'" + spec + "': expected SIZE[@COLOR]:COUNT, as in 2x4:100");
  const std::string what = spec.substr(0, colon);
  const int count = parse_count(trim(spec.substr(colon + 1)), where, 0);
  const auto at = what.find('@');
  auto [l, w] = parse_size(trim(what.substr(0, at)), catalog, where, 0);
  if (at == std::string::npos)
    by_size[{l, w}] = count;
  else
    by_size_color[{l, w, parse_color(trim(what.substr(at + 1)), where, 0)}] = count;
}

void Limits::read_inventory(const std::filesystem::path& csv, const BrickCatalog& catalog) {
  const std::string file = csv.string();
  // A device or a pipe never ends (/dev/zero filled the memory, a FIFO blocked): an inventory is
  // a file, and a list of parts is small.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(csv, ec))
    throw InputError(file, 0,
                     std::filesystem::exists(csv, ec) ? "the inventory is not a regular file"
                                                      : "no such inventory file");
  if (std::filesystem::file_size(csv, ec) > kMaxInventoryBytes)
    throw InputError(file, 0, "the inventory is over 16 MB: not a list of parts");
  std::ifstream in(csv);
  if (!in) throw InputError(file, 0, "cannot read the inventory");
  listed_only = true;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const std::string row = trim(text);
    if (row.empty() || row[0] == '#') continue;
    const std::vector<std::string> fields = split_csv(row);
    if (line == 1 && !fields.empty() && fields[0] == "part") continue;  // the header
    if (fields.size() != 3)
      throw InputError(
          file, line,
          "expected part,color,quantity (" + std::to_string(fields.size()) + " fields)");
    auto [l, w] = parse_size(fields[0], catalog, file, line);
    const int count = parse_count(fields[2], file, line);
    if (fields[1].empty())
      by_size[{l, w}] += count;
    else
      by_size_color[{l, w, parse_color(fields[1], file, line)}] += count;
  }
}

}  // namespace lego::layout
