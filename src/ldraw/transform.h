#pragma once
#include <array>
#include <cmath>

namespace lego::ldraw {

// An LDraw placement: world = rot * local + pos, rot row-major (a b c / d e f / g h i).
struct Transform {
  std::array<double, 3> pos{0, 0, 0};
  std::array<double, 9> rot{1, 0, 0, 0, 1, 0, 0, 0, 1};

  Transform then(const Transform& child) const {  // this ∘ child
    Transform out;
    for (int r = 0; r < 3; ++r) {
      out.pos[r] = pos[r];
      for (int k = 0; k < 3; ++k) out.pos[r] += rot[3 * r + k] * child.pos[k];
      for (int c = 0; c < 3; ++c) {
        double s = 0;
        for (int k = 0; k < 3; ++k) s += rot[3 * r + k] * child.rot[3 * k + c];
        out.rot[3 * r + c] = s;
      }
    }
    return out;
  }
  double determinant() const {
    const auto& m = rot;
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
           m[2] * (m[3] * m[7] - m[4] * m[6]);
  }
  // True when the rows are orthonormal (a rotation or a mirror), to tolerance.
  bool orthonormal(double tol = 1e-3) const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double d = 0;
        for (int k = 0; k < 3; ++k) d += rot[3 * i + k] * rot[3 * j + k];
        if (std::abs(d - (i == j ? 1.0 : 0.0)) > tol) return false;
      }
    return true;
  }
};

}  // namespace lego::ldraw
