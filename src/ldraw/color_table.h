#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace lego::ldraw {

inline constexpr int kMainColor = 16;  // "inherit the colour of the including line"
inline constexpr int kEdgeColor = 24;  // "the edge colour of the including line's colour"

// LDraw direct colours 0x2RRGGBB are encoded as codes at or above this value.
inline constexpr int kDirectColorBase = 0x2000000;

struct Color {
  int code = 0;
  std::string name;
  unsigned rgb = 0;
  unsigned edge_rgb = 0;
  int alpha = 255;  // ALPHA: below 255 a transparent colour
};

// An LDraw colour table built from `0 !COLOUR` lines (LDConfig.ldr or a model's own).
class ColorTable {
 public:
  static ColorTable load(const std::filesystem::path& ldconfig);
  static const ColorTable& standard();  // ldraw_parts/LDConfig.ldr

  // Parses one `0 !COLOUR ...` line (the text after "0 "); false if it is not a valid one.
  bool add_definition(std::string_view meta_line);
  // Adds `other`'s colours whose codes this table lacks.
  void add_missing(const ColorTable& other);
  const Color* find(int code) const;
  std::string name(int code) const;  // "Red", "#1A2B3C" for direct colours, "colour 999" if unknown
  std::optional<unsigned> rgb(int code) const;
  const std::map<int, Color>& colors() const { return colors_; }

 private:
  std::map<int, Color> colors_;
};

// Parses an LDraw colour field: a decimal code or a direct colour "0x2RRGGBB".
std::optional<int> parse_color_code(std::string_view token);

}  // namespace lego::ldraw
