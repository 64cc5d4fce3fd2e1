#pragma once
// The table a model rests on (docs/physics.md, "Ground"). A model whose lowest points are level
// and around its centre of mass rests on them, the table level. One whose lowest point is off to
// a side (a steamroller's front roller drawn 4 LDU below its rear tyres) tips onto what else is
// low until its centre of mass is over what it rests on, as it would on a real table: the table
// is then the highest plane under every point of the model, at its centre of mass. The tilt is
// small and gravity is taken straight down as before.
#include <array>
#include <vector>

#include "core/assembly.h"
#include "core/part_shape.h"

namespace lego::physics {

// A model settles on a table: parts whose bottom is within this of it (LDU) stand on it too.
// Measured on the corpus: a dozer drawn with its blade 2 LDU below its tyres, or a tower with one
// ornament 2 LDU below its legs, otherwise rests on that one part and tips.
inline constexpr double kSettleLdu = 3.0;
// A model that would have to tilt further than this to rest tips over whatever the table does.
inline constexpr double kMaxTableSlope = 0.25;  // about 14 degrees

struct Table {
  double height = 0;                  // at x = z = 0 (LDU, lattice frame, y up)
  std::array<double, 2> slope{0, 0};  // its rise per LDU along x and along z
  // The model's centre of mass is over nothing it could rest on, however the table tilts (up to
  // kMaxTableSlope): it tips over. The table is then level at its lowest point.
  bool tips = false;
  double at(double x, double z) const { return height + slope[0] * x + slope[1] * z; }
  bool level() const { return slope[0] == 0 && slope[1] == 0; }
};

// `points`: where the model reaches down, in the lattice frame; `centre`: its centre of mass.
// `settle`: how far above the lowest point a part still stands on a level table.
Table rest_on_table(const std::vector<Vec3>& points, const Vec3& centre, double settle);

struct ContactGraph;
struct Connectivity;
// The table under what stands of an assembly analysed on a level table at its lowest point (its
// graph and connectivity): from the bottom corners of its grounded parts' bodies and the outlines
// of the carried parts that do not float, within a plate of the lowest, and their centre of
// mass. What floats has no say: a part hanging in the air does not tilt the table under the rest.
Table settle_on_table(const Assembly& assembly, const ContactGraph& graph,
                      const Connectivity& connectivity);

}  // namespace lego::physics
