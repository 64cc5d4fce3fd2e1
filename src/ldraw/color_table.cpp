#include "ldraw/color_table.h"

#include <algorithm>

#include <fmt/format.h>
#include <charconv>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/brick_catalog.h"
#include "core/error.h"

namespace lego::ldraw {
namespace {

std::optional<unsigned> parse_hex_rgb(std::string_view s) {
  if (s.starts_with("#"))
    s.remove_prefix(1);
  else if (s.starts_with("0x") || s.starts_with("0X"))
    s.remove_prefix(2);
  if (s.size() != 6) return std::nullopt;
  unsigned value = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), value, 16);
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return value;
}

}  // namespace

std::optional<int> parse_color_code(std::string_view token) {
  if (token.starts_with("0x") || token.starts_with("0X")) {
    std::string_view hex = token.substr(2);
    if (hex.size() != 7 || hex[0] != '2') return std::nullopt;
    auto rgb = parse_hex_rgb(hex.substr(1));
    if (!rgb) return std::nullopt;
    return kDirectColorBase + int(*rgb);
  }
  int code = 0;
  auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), code);
  if (ec != std::errc() || p != token.data() + token.size() || code < 0) return std::nullopt;
  return code;
}

bool ColorTable::add_definition(std::string_view meta_line) {
  std::istringstream in{std::string(meta_line)};
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  if (words.size() < 2 || words[0] != "!COLOUR") return false;
  Color color;
  color.name = words[1];
  bool have_code = false, have_value = false;
  for (size_t i = 2; i + 1 < words.size(); ++i) {
    if (words[i] == "CODE") {
      auto code = parse_color_code(words[i + 1]);
      if (!code) return false;
      color.code = *code;
      have_code = true;
    } else if (words[i] == "VALUE") {
      auto rgb = parse_hex_rgb(words[i + 1]);
      if (!rgb) return false;
      color.rgb = *rgb;
      have_value = true;
    } else if (words[i] == "ALPHA") {
      try {
        color.alpha = std::clamp(std::stoi(words[i + 1]), 0, 255);
      } catch (const std::exception&) {
        return false;
      }
    } else if (words[i] == "EDGE") {
      // EDGE may name another colour code instead of an RGB value.
      if (auto rgb = parse_hex_rgb(words[i + 1]))
        color.edge_rgb = *rgb;
      else if (auto code = parse_color_code(words[i + 1]); code && find(*code))
        color.edge_rgb = find(*code)->rgb;
    }
  }
  if (!have_code || !have_value) return false;
  colors_[color.code] = color;
  return true;
}

void ColorTable::add_missing(const ColorTable& other) {
  for (const auto& [code, color] : other.colors_) colors_.try_emplace(code, color);
}

ColorTable ColorTable::load(const std::filesystem::path& ldconfig) {
  std::ifstream in(ldconfig);
  if (!in) throw InputError(ldconfig.string(), 0, "cannot open the colour table");
  ColorTable table;
  std::string line;
  while (std::getline(in, line)) {
    std::string_view v(line);
    if (v.starts_with("0 ")) table.add_definition(v.substr(2));
  }
  return table;
}

const ColorTable& ColorTable::standard() {
  static const ColorTable table = load(default_parts_dir() / "LDConfig.ldr");
  return table;
}

const Color* ColorTable::find(int code) const {
  auto it = colors_.find(code);
  return it == colors_.end() ? nullptr : &it->second;
}

std::optional<unsigned> ColorTable::rgb(int code) const {
  if (code >= kDirectColorBase) return unsigned(code - kDirectColorBase);
  if (const Color* c = find(code)) return c->rgb;
  return std::nullopt;
}

std::string ColorTable::name(int code) const {
  if (code >= kDirectColorBase) return fmt::format("#{:06X}", code - kDirectColorBase);
  if (const Color* c = find(code)) return c->name;
  return fmt::format("colour {}", code);
}

}  // namespace lego::ldraw
