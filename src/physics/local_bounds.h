#pragma once
// Bounds on the C_M of an assembly that differs from an analysed one in a few bricks, from two
// LPs over those bricks and a ring of unchanged bricks around them (the region), never the whole
// model's. docs/stability-lp.md "Local bounds" derives them.
// - Lower: the analysed forces are kept outside the region, the region's forces are solved for
//   with the forces across its boundary fixed. That is an equilibrium of the whole assembly, so
//   its C_M is reached: C_M ≥ lower.
// - Upper: the analysed LP's duals are kept outside the region and the region's are optimized
//   (the dual of the region's LP with the boundary forces priced by the outside duals). Any dual
//   solution bounds the scaled LP's w from above: C_M ≤ upper.
// Both are as accurate as the solver (the analysis promises C_M to 1e-6 relative).
#include <limits>

#include "core/assembly.h"
#include "physics/stability.h"

namespace lego::physics {

struct CmBounds {
  // False when the assemblies could not be matched brick for brick outside the region (or the
  // analysis carries no forces): both bounds are then open.
  bool valid = false;
  double lower = -std::numeric_limits<double>::infinity();  // g·m/s²
  double upper = std::numeric_limits<double>::infinity();
  int changed_bricks = 0, region_bricks = 0;
  double seconds = 0;

  double lower_gf() const { return lower / kGravity; }
  double upper_gf() const { return upper / kGravity; }
};

struct LocalBoundOptions {
  // The region: the changed bricks, every brick that shares a force with one, and `ring` more
  // layers of neighbours.
  int ring = 2;
  // Past this share of the model a region's LP costs nearly what the whole model's does, and
  // the bounds are left open.
  double max_region_share = 1.0;
  bool lower = true, upper = true;  // which bounds to compute (the other stays open)
  StabilityOptions stability;       // how the region's LPs are solved
};

// `before_result` must be analyze_stability(before) (Solved, with its forces and duals). Bricks of
// `after` equal in place, size and height to a brick of `before` are unchanged. Loads outside the
// region must be the same in both.
CmBounds bound_cm_locally(const Assembly& before, const StabilityResult& before_result,
                          const Assembly& after, const LocalBoundOptions& options = {});

}  // namespace lego::physics
