#include "voxel/palette.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"

namespace lego::voxel {
namespace {

double linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double f(double t) {
  return t > 216.0 / 24389 ? std::cbrt(t) : (24389.0 / 27 * t + 16) / 116;
}
double deg(double rad) {
  return rad * 180 / std::numbers::pi;
}
double rad(double deg) {
  return deg * std::numbers::pi / 180;
}

}  // namespace

mesh::Rgb from_hex(unsigned rgb) {
  return {((rgb >> 16) & 255) / 255.0f, ((rgb >> 8) & 255) / 255.0f, (rgb & 255) / 255.0f};
}

Lab to_lab(const mesh::Rgb& c) {
  const double r = linear(std::clamp(double(c.r), 0.0, 1.0)),
               g = linear(std::clamp(double(c.g), 0.0, 1.0)),
               b = linear(std::clamp(double(c.b), 0.0, 1.0));
  // sRGB (D65) to XYZ, relative to the D65 white.
  const double x = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
  return {116 * f(y) - 16, 500 * (f(x) - f(y)), 200 * (f(y) - f(z))};
}

namespace {

// CIEDE2000 (Sharma, Wu, Dalal 2005), with kL = kC = kH = 1; `rotation`: with its blue-region
// rotation term R_T.
double ciede2000(const Lab& p, const Lab& q, bool rotation) {
  const double c1 = std::hypot(p.a, p.b), c2 = std::hypot(q.a, q.b), cm = (c1 + c2) / 2;
  const double g = 0.5 * (1 - std::sqrt(std::pow(cm, 7) / (std::pow(cm, 7) + std::pow(25.0, 7))));
  const double a1 = (1 + g) * p.a, a2 = (1 + g) * q.a;
  const double c1p = std::hypot(a1, p.b), c2p = std::hypot(a2, q.b);
  auto hue = [](double b, double a) {
    if (a == 0 && b == 0) return 0.0;
    double h = deg(std::atan2(b, a));
    return h < 0 ? h + 360 : h;
  };
  const double h1 = hue(p.b, a1), h2 = hue(q.b, a2);
  const double dl = q.l - p.l, dc = c2p - c1p;
  double dh = 0;
  if (c1p * c2p != 0) {
    dh = h2 - h1;
    if (dh > 180)
      dh -= 360;
    else if (dh < -180)
      dh += 360;
  }
  const double dH = 2 * std::sqrt(c1p * c2p) * std::sin(rad(dh / 2));
  const double lm = (p.l + q.l) / 2, cmp = (c1p + c2p) / 2;
  double hm = h1 + h2;
  if (c1p * c2p != 0) {
    if (std::abs(h1 - h2) > 180) hm += h1 + h2 < 360 ? 360 : -360;
    hm /= 2;
  }
  const double t = 1 - 0.17 * std::cos(rad(hm - 30)) + 0.24 * std::cos(rad(2 * hm)) +
                   0.32 * std::cos(rad(3 * hm + 6)) - 0.20 * std::cos(rad(4 * hm - 63));
  const double sl = 1 + 0.015 * (lm - 50) * (lm - 50) / std::sqrt(20 + (lm - 50) * (lm - 50));
  const double sc = 1 + 0.045 * cmp, sh = 1 + 0.015 * cmp * t;
  const double rt = -2 * std::sqrt(std::pow(cmp, 7) / (std::pow(cmp, 7) + std::pow(25.0, 7))) *
                    std::sin(rad(60 * std::exp(-std::pow((hm - 275) / 25, 2))));
  const double x = dl / sl, y = dc / sc, z = dH / sh;
  return std::sqrt(x * x + y * y + z * z + (rotation ? rt * y * z : 0.0));
}

}  // namespace

double ciede2000(const Lab& x, const Lab& y) {
  return ciede2000(x, y, true);
}

double match_distance(const Lab& x, const Lab& y) {
  return ciede2000(x, y, false);
}

Palette Palette::of(const std::vector<int>& codes, const ldraw::ColorTable& table) {
  Palette p;
  for (int code : codes) {
    const ldraw::Color* c = table.find(code);
    if (!c || code == ldraw::kMainColor || code == ldraw::kEdgeColor)
      throw InputError("", 0, fmt::format("LDraw colour {} is not in the colour table", code));
    p.codes_.push_back(code);
    p.lab_.push_back(to_lab(from_hex(c->rgb)));
  }
  if (p.codes_.empty()) throw InputError("", 0, "the palette has no colour");
  return p;
}

const std::vector<int>& Palette::current_codes() {
  static const std::vector<int> codes = {
      15, 0,   71,  72, 4,  320, 1,   272, 73, 212, 321, 322, 2,  288, 10, 27, 326, 330, 14, 226,
      25, 191, 484, 19, 28, 70,  308, 78,  84, 92,  5,   26,  29, 30,  31, 3,  323, 378, 379};
  return codes;
}

Palette Palette::current(const ldraw::ColorTable& table) {
  return of(current_codes(), table);
}

bool Palette::contains(int code) const {
  return std::find(codes_.begin(), codes_.end(), code) != codes_.end();
}

Palette Palette::with(int code, const ldraw::ColorTable& table) const {
  if (contains(code)) return *this;
  std::vector<int> codes = codes_;
  codes.push_back(code);
  return of(codes, table);
}

Palette Palette::paper(const ldraw::ColorTable& table) {
  return of({15, 4, 1, 2, 14, 0, 6, 25}, table);
}

Palette Palette::all(const ldraw::ColorTable& table) {
  std::vector<int> codes;
  // Solid colours only: a sculpture's shell is not glass (the table has Trans_Clear for booklets).
  for (const auto& [code, c] : table.colors())
    if (code != ldraw::kMainColor && code != ldraw::kEdgeColor && code < ldraw::kDirectColorBase &&
        c.alpha == 255)
      codes.push_back(code);
  return of(codes, table);
}

int Palette::nearest(const mesh::Rgb& srgb) const {
  const Lab lab = to_lab(srgb);
  double best = std::numeric_limits<double>::infinity();
  int code = codes_.front();
  for (size_t i = 0; i < codes_.size(); ++i)
    if (double d = match_distance(lab, lab_[i]); d < best) best = d, code = codes_[i];
  return code;
}

}  // namespace lego::voxel
