#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "../../tools/bench/shapes.h"
#include "physics/builders.h"
#include "physics/certificate.h"
#include "physics/stability.h"
#include "physics/step_stability.h"

namespace lego::physics {
namespace {

using test::add;
using test::kBrick;

// The certificate of `a` (from no forces), with the exact analysis to compare it with.
struct Both {
  Certificate certificate;
  StabilityResult exact;
};

Both certify_and_solve(const Assembly& a) {
  Both out;
  out.exact = analyze_contacts(a, {});
  const EquilibriumSystem sys = build_equilibrium(a, out.exact, {});
  out.certificate = certify(sys, out.exact.graph);
  solve_equilibrium(a, sys, {}, out.exact);
  return out;
}

TEST(Certificate, ASingleCantileverIsCertifiedExactly) {
  Assembly a;
  add(a, "3622", 0, 0, 0);
  add(a, "3008", 0, kBrick, 0);
  const Both b = certify_and_solve(a);
  ASSERT_TRUE(b.certificate.found) << b.certificate.why_not;
  EXPECT_NEAR(b.certificate.cm / kGravity, b.exact.cm_gf(), 1e-6);
}

// Figure 7 (b) holds its 1x8s by the 1x2s above the joints pulling while the 1x8s' end faces
// push: without the faces side by side the certificate was 6.9 gf of (b) 4's 61.1.
TEST(Certificate, Figure7BridgesAreCertifiedNearTheirCm) {
  for (int n = 1; n <= 8; ++n)
    for (char variant : {'a', 'b'}) {
      const Both b = certify_and_solve(test::figure7_bridge(n, variant));
      if (b.exact.cm_gf() <= 0) continue;
      ASSERT_TRUE(b.certificate.found) << variant << n << ": " << b.certificate.why_not;
      EXPECT_LE(b.certificate.cm / kGravity, b.exact.cm_gf() + 1e-6) << variant << n;
      EXPECT_GE(b.certificate.cm / kGravity, 0.9 * b.exact.cm_gf()) << variant << n;
    }
}

TEST(Certificate, HollowBoxesWithALedge) {
  for (int bricks : {50, 200, 800}) {
    const Both b = certify_and_solve(bench::hollow_box_of(bricks));
    ASSERT_TRUE(b.certificate.found) << bricks << ": " << b.certificate.why_not;
    EXPECT_LE(b.certificate.cm / kGravity, b.exact.cm_gf() + 1e-6) << bricks;
    EXPECT_GE(b.certificate.cm / kGravity, 0.95 * b.exact.cm_gf()) << bricks;
  }
}

TEST(Certificate, NoneForAModelThatFalls) {
  const Both b = certify_and_solve(test::figure7_bridge(6, 'a'));  // falls at 5 (the paper)
  EXPECT_LT(b.exact.cm_gf(), 0);
  EXPECT_FALSE(b.certificate.found);
}

// Random stacks: bricks on the knobs of bricks below, overhanging as they come, built layer by
// layer (some fall off: floating, left out of both). Every step that a certificate (begun from
// the step before's) says stands has an exact C_M at least the certificate's.
TEST(Certificate, AStepsCertificateNeverExceedsItsExactCm) {
  const char* parts[] = {"3001", "3002", "3003", "3004", "3005", "3010", "3009", "3008", "3622"};
  int certified = 0, checked = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(seed);
    Assembly whole;
    const int layers = 6;
    for (int layer = 0; layer < layers; ++layer)
      for (int k = 0; k < 10; ++k) {
        const int x = int(rng() % 12), z = int(rng() % 12);
        Brick b;
        b.type = BrickCatalog::standard().find(parts[rng() % std::size(parts)]);
        b.min = {x, layer * kBrick, z};
        b.rotated = rng() % 2;
        b.color = 4;
        const int sx = b.rotated ? b.type->width : b.type->length;
        const int sz = b.rotated ? b.type->length : b.type->width;
        const bool overlaps =
            std::any_of(whole.bricks.begin(), whole.bricks.end(), [&](const Brick& o) {
              const int ox = o.rotated ? o.type->width : o.type->length;
              const int oz = o.rotated ? o.type->length : o.type->width;
              return o.min.y == b.min.y && o.min.x < x + sx && x < o.min.x + ox &&
                     o.min.z < z + sz && z < o.min.z + oz;
            });
        if (!overlaps) whole.bricks.push_back(b);
      }
    StepForces built;
    for (int layer = 0; layer < layers; ++layer) {
      Assembly partial;
      std::vector<int> whole_index;
      for (int i = 0; i < int(whole.bricks.size()); ++i)
        if (whole.bricks[size_t(i)].min.y <= layer * kBrick) {
          whole_index.push_back(i);
          partial.bricks.push_back(whole.bricks[size_t(i)]);
        }
      partial.ground_height = 0;
      const StepStability step = analyze_step(partial, whole_index, built, {}, 0.0);
      const StabilityResult exact = analyze_stability(partial);
      ++checked;
      if (!step.result.certified) continue;
      ++certified;
      EXPECT_LE(step.result.cm_gf(), exact.cm_gf() + 1e-6) << "seed " << seed << " layer " << layer;
      EXPECT_GT(exact.cm_gf(), 0) << "seed " << seed << " layer " << layer;
      EXPECT_EQ(step.result.stable(), exact.stable()) << "seed " << seed << " layer " << layer;
      built = step.forces;
    }
  }
  EXPECT_GT(certified, checked / 3) << "certified " << certified << " of " << checked;
}

}  // namespace
}  // namespace lego::physics
