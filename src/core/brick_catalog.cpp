#include "core/brick_catalog.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "core/csv.h"
#include "core/error.h"

namespace lego {

std::string normalize_reference(std::string_view name) {
  std::string out;
  out.reserve(name.size());
  for (char c : name)
    out.push_back(c == '\\' ? '/' : char(std::tolower(static_cast<unsigned char>(c))));
  return out;
}

std::string normalize_part_name(std::string_view name) {
  std::string out = normalize_reference(name);
  if (out.starts_with("parts/")) out.erase(0, 6);
  if (out.ends_with(".dat")) out.resize(out.size() - 4);
  return out;
}

BrickCatalog BrickCatalog::load(const std::filesystem::path& csv_file) {
  std::ifstream in(csv_file);
  if (!in) throw InputError(csv_file.string(), 0, "cannot open the brick catalog");
  BrickCatalog catalog;
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    auto fields = split_csv(line);
    if (header.empty()) {
      header = fields;
      continue;
    }
    if (fields.size() != header.size())
      throw InputError(csv_file.string(), line_no,
                       "expected " + std::to_string(header.size()) + " fields");
    auto get = [&](const char* column) -> const std::string& {
      auto it = std::find(header.begin(), header.end(), column);
      if (it == header.end())
        throw InputError(csv_file.string(), 1, std::string("missing column ") + column);
      return fields[it - header.begin()];
    };
    BrickType type;
    try {
      type.part = normalize_part_name(get("part"));
      type.name = get("name");
      type.kind = get("kind");
      type.length = std::stoi(get("length"));
      type.width = std::stoi(get("width"));
      type.height = std::stoi(get("height"));
      type.mass_g = std::stod(get("mass_g"));
      type.mass_source = get("mass_source");
    } catch (const std::invalid_argument&) {
      throw InputError(csv_file.string(), line_no, "a number field is not a number");
    }
    if (type.length < type.width || type.width < 1 || type.height < 1 || type.mass_g <= 0)
      throw InputError(csv_file.string(), line_no, "implausible dimensions or mass");
    catalog.add(std::move(type));
  }
  if (catalog.types_.empty())
    throw InputError(csv_file.string(), line_no, "the catalog lists no part");
  return catalog;
}

const BrickCatalog& BrickCatalog::standard() {
  static const BrickCatalog catalog = load(default_parts_dir() / "catalog.csv");
  return catalog;
}

const BrickType& BrickCatalog::add(BrickType type) {
  if (type.shape.body.empty())
    type.shape = box_brick_shape(type.length, type.width, type.height, type.has_knobs);
  std::string key = type.part;
  const BrickType& stored = types_.emplace_back(std::move(type));
  by_part_[key] = &stored;
  return stored;
}

const BrickType* BrickCatalog::find(std::string_view part) const {
  auto it = by_part_.find(normalize_part_name(part));
  return it == by_part_.end() ? nullptr : it->second;
}

const BrickType* BrickCatalog::find_by_size(int length, int width, int height) const {
  if (length < width) std::swap(length, width);
  for (const auto& t : types_)
    if (t.length == length && t.width == width && t.height == height && t.has_knobs) return &t;
  return nullptr;
}

std::filesystem::path default_parts_dir() {
  if (const char* env = std::getenv("LEGOLIZATION_PARTS"); env && *env) return env;
  return LEGOLIZATION_PARTS_DIR;
}

}  // namespace lego
