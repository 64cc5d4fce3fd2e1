#pragma once
// Mapping surface colors to the LDraw colors a builder has, by perceptual distance in CIELAB
// (match_distance, close to CIEDE2000), and measuring the result (CIEDE2000). Colors are taken as
// sRGB, as LDraw's are and as most mesh files write them.
#include <array>
#include <string>
#include <vector>

#include "ldraw/color_table.h"
#include "mesh/mesh.h"

namespace lego::voxel {

struct Lab {
  double l = 0, a = 0, b = 0;
};
Lab to_lab(const mesh::Rgb& srgb);
mesh::Rgb from_hex(unsigned rgb);  // 0xRRGGBB, as LDraw colour tables give it
double ciede2000(const Lab& x, const Lab& y);

// The distance a surface is matched to the palette by: CIEDE2000 without its rotation term R_T.
// R_T tilts the tolerance ellipses in the blue region, fitted to small differences; between a
// surface and a palette the differences are large, and there it pulls saturated dark blues to
// black (navy #000080 to LDraw 0 rather than 272 Dark Blue or 1 Blue). Without it every case of
// tests/voxel (Palette.*) lands in its colour family, in the current palette and the paper's.
double match_distance(const Lab& x, const Lab& y);

class Palette {
 public:
  // The default: solid colours LEGO makes today in the common bricks, each with a BrickLink
  // colour (ldraw_parts/bricklink.csv), so the parts list can be bought. No retired colour
  // (6 Brown, 7 Light Grey, 8 Dark Grey): their bricks are found only second hand.
  static Palette current(const ldraw::ColorTable& table);
  static const std::vector<int>& current_codes();
  // The paper's eight: white, red, blue, green, yellow, black, brown (LDraw 6), orange.
  static Palette paper(const ldraw::ColorTable& table);
  // Every solid color of the table (not 16, 24 or direct colors).
  static Palette all(const ldraw::ColorTable& table);
  // These codes; throws InputError naming an unknown code.
  static Palette of(const std::vector<int>& codes, const ldraw::ColorTable& table);

  int nearest(const mesh::Rgb& srgb) const;  // the LDraw code closest by match_distance
  bool contains(int code) const;
  // This palette with `code` added (when it is not in it yet).
  Palette with(int code, const ldraw::ColorTable& table) const;
  const std::vector<int>& codes() const { return codes_; }

 private:
  std::vector<int> codes_;
  std::vector<Lab> lab_;
};

}  // namespace lego::voxel
