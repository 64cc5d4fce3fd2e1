#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/brick_catalog.h"
#include "core/lattice.h"
#include "core/part_shape.h"

namespace lego {

// Where a brick came from when it was read from LDraw (empty file when generated).
struct SourceRef {
  std::string file;
  int line = 0;
  int step = 0;  // 1-based build step of the main model, 0 when unknown
  // Built apart in a sub-assembly (ldraw::PlacedPart::built_in, apart_from): the step that builds
  // it, and the sub-assembly's first step; 0 when built in place.
  int built_in = 0, apart_from = 0;
};

// Where a part is, as LDraw places it: world = rotation · local + origin, in LDraw's frame (LDU,
// -y up), relative to Assembly::origin_ldu. For an analysed part the rotation turns by multiples
// of 90 degrees (a signed permutation, perhaps mirrored).
struct Pose {
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  Vec3 origin{0, 0, 0};

  Vec3 apply(const Vec3& local) const {
    Vec3 out = origin;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) out[r] += rotation[3 * r + k] * local[k];
    return out;
  }
  // A direction of the part's frame in LDraw's frame.
  Vec3 rotate(const Vec3& direction) const {
    Vec3 out{0, 0, 0};
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) out[r] += rotation[3 * r + k] * direction[k];
    return out;
  }
  // This pose after `inner`: where `inner` puts a part, taken through this pose.
  Pose then(const Pose& inner) const {
    Pose out;
    out.origin = apply(inner.origin);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        double v = 0;
        for (int k = 0; k < 3; ++k) v += rotation[3 * r + k] * inner.rotation[3 * k + c];
        out.rotation[3 * r + c] = v;
      }
    return out;
  }
  // A direction of the part's frame in LDraw's frame (rotation must be a signed permutation).
  int turn(int direction) const;
};

// The lattice frame: LDU, y up (LDraw's y flipped). The physics works in it; this is the one
// place LDraw's frame turns into it.
inline Vec3 lattice_from_ldraw(const Vec3& p) {
  return {p[0], -p[1], p[2]};
}
inline int lattice_direction(int ldraw_direction) {
  return axis_of(ldraw_direction) == 1 ? opposite(ldraw_direction) : ldraw_direction;
}

// A lattice of its own (docs/what-it-analyses.md, turned lattices): the parts inside a submodel
// that the model places at an angle that is not a multiple of 90 degrees (a stand turned on its
// base, a roof tilted on hinges) lie on the submodel's lattice. Their poses are in that frame, and
// `pose` puts the frame in the model.
struct LatticeFrame {
  int id = 0;  // bricks whose frames share an id share one lattice
  Pose pose;   // any rotation
};
// Whether a frame's up is not the model's (by more than the degree a quarter turn allows).
inline bool tilted(const LatticeFrame& frame) {
  return frame.pose.rotation[4] < 0.9994;  // cos 2°
}

// A brick on the lattice: the lattice cell of its minimum corner, turned 0 or 90 degrees about
// the vertical. At 0 degrees its length runs along x; at 90 degrees along z. A part read from
// LDraw has its exact pose instead (any turn by multiples of 90 degrees, anywhere): `pose`.
struct Brick {
  const BrickType* type = nullptr;
  LatticePoint min;  // x, z in studs; y in plates (the bottom face); when `pose` is unset
  bool rotated = false;
  std::optional<Pose> pose;
  std::optional<LatticeFrame> frame;  // when set, `pose` is in this frame, not the model's
  int color = 16;                     // LDraw colour code
  SourceRef source;
  bool fixed = false;  // part of the ground: a baseplate at the bottom, or named so by the user
  // Not the model's: a column legolize adds under what hangs, built first and taken away once the
  // model stands (layout/supports.h).
  bool support = false;

  int size_x() const { return rotated ? type->width : type->length; }
  int size_z() const { return rotated ? type->length : type->width; }
  int height() const { return type->height; }
  int max_x() const { return min.x + size_x(); }  // exclusive
  int max_z() const { return min.z + size_z(); }
  int top() const { return min.y + height(); }
  double mass_g() const { return type->mass_g; }
};

// The pose of any brick: `pose` when set, else the one its lattice cell and turn give (origin at
// the top centre of the body, as LDraw parts have it).
Pose pose_of(const Brick& brick);
// Where the model puts it: pose_of, through its frame when it has one.
Pose model_pose(const Brick& brick);

}  // namespace lego
