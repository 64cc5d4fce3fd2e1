#pragma once
// Mapping surface colors to the LDraw colors a builder has, by perceptual distance (CIEDE2000 in
// CIELAB). Colors are taken as sRGB, as LDraw's are and as most mesh files write them.
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

class Palette {
 public:
  // The paper's eight: white, red, blue, green, yellow, black, brown, orange.
  static Palette paper(const ldraw::ColorTable& table);
  // Every solid color of the table (not 16, 24 or direct colors).
  static Palette all(const ldraw::ColorTable& table);
  // These codes; throws InputError naming an unknown code.
  static Palette of(const std::vector<int>& codes, const ldraw::ColorTable& table);

  int nearest(const mesh::Rgb& srgb) const;  // the LDraw code closest in CIEDE2000
  const std::vector<int>& codes() const { return codes_; }

 private:
  std::vector<int> codes_;
  std::vector<Lab> lab_;
};

}  // namespace lego::voxel
