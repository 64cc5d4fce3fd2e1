#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include <fmt/format.h>
#include <Eigen/Dense>

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

// A spread that leaves a force pulling is mended by a small LP: the spread here (a stand-in)
// moves the body-by-body forces along a direction that balances itself (a knob's push taken
// back by the other knobs between the same two bricks) until one push pulls by a gram-force.
TEST(Certificate, ForcesASpreadLeavesPastTheirBoundsAreBroughtBack) {
  Assembly a;
  add(a, "3001", 0, 0, 0);
  add(a, "3001", 2, kBrick, 0);  // half over the one below
  add(a, "3001", 0, 2 * kBrick, 0);
  StabilityResult r = analyze_contacts(a, {});
  const EquilibriumSystem sys = build_equilibrium(a, r, {});
  solve_equilibrium(a, sys, {}, r);
  ASSERT_TRUE(r.stable());
  auto bodies_of = [&](int j) {
    std::vector<int> out;
    for (int e = sys.column_start[size_t(j)]; e < sys.column_start[size_t(j) + 1]; ++e)
      if (out.empty() || out.back() != EquilibriumSystem::body_of_row(sys.row_index[size_t(e)]))
        out.push_back(EquilibriumSystem::body_of_row(sys.row_index[size_t(e)]));
    return out;
  };
  auto on_body = [&](int j, int body) {
    Eigen::Matrix<double, 6, 1> v = Eigen::Matrix<double, 6, 1>::Zero();
    for (int e = sys.column_start[size_t(j)]; e < sys.column_start[size_t(j) + 1]; ++e)
      if (EquilibriumSystem::body_of_row(sys.row_index[size_t(e)]) == body)
        v[sys.row_index[size_t(e)] % 6] += sys.value[size_t(e)];
    return v;
  };
  // A push between the two upper bricks, and the direction: +1 on it, the least-squares
  // combination of the other columns between the same two bricks that acts as it does, negated.
  std::vector<double> direction(size_t(sys.columns()), 0.0);
  int push = -1;
  for (int j = 0; j < sys.columns() && push < 0; ++j) {
    const std::vector<int> pair = bodies_of(j);
    if (sys.kind[size_t(j)] != ForceKind::Normal || pair.size() != 2) continue;
    std::vector<int> others;
    for (int k = 0; k < sys.columns(); ++k)
      if (k != j && sys.kind[size_t(k)] != ForceKind::Support && bodies_of(k) == pair)
        others.push_back(k);
    Eigen::MatrixXd m(6, Eigen::Index(others.size()));
    for (size_t k = 0; k < others.size(); ++k) m.col(Eigen::Index(k)) = on_body(others[k], pair[0]);
    const Eigen::VectorXd c = m.completeOrthogonalDecomposition().solve(on_body(j, pair[0]));
    if ((m * c - on_body(j, pair[0])).norm() > 1e-9) continue;
    push = j;
    direction[size_t(j)] = 1;
    for (size_t k = 0; k < others.size(); ++k) direction[size_t(others[k])] = -c[Eigen::Index(k)];
  }
  ASSERT_GE(push, 0) << "no push whose action the other columns of its two bricks take";
  Spreading spreading;
  spreading.bodies.assign(size_t(sys.rows / EquilibriumSystem::kEquations), 0);
  spreading.spread = [&](std::vector<double>& x) {
    const double by = x[size_t(push)] + kGravity;  // leaves it pulling by a gram-force
    for (size_t j = 0; j < x.size(); ++j) x[j] -= by * direction[j];
    return true;
  };
  const Certificate c = certify(sys, r.graph, {}, &spreading);
  ASSERT_TRUE(c.found) << c.why_not;
  EXPECT_GE(c.mended, 1);
  EXPECT_LE(c.cm / kGravity, r.cm_gf() + 1e-6);
  // Without the mending the same forces would not have passed the check: the push pulls.
  Spreading unmended = spreading;
  std::vector<double> left;
  unmended.spread = [&](std::vector<double>& x) {
    spreading.spread(x);
    left = x;
    return true;
  };
  certify(sys, r.graph, {}, &unmended);
  EXPECT_LT(left[size_t(push)], -0.5 * kGravity);
}

// Bricks on the knobs of bricks below, overhanging as they come, `layers` high (some fall off:
// floating, left out of every analysis).
Assembly random_stack(unsigned seed, int layers) {
  const char* parts[] = {"3001", "3002", "3003", "3004", "3005", "3010", "3009", "3008", "3622"};
  std::mt19937 rng(seed);
  Assembly whole;
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
            return o.min.y == b.min.y && o.min.x < x + sx && x < o.min.x + ox && o.min.z < z + sz &&
                   z < o.min.z + oz;
          });
      if (!overlaps) whole.bricks.push_back(b);
    }
  return whole;
}

// The bricks of `whole` up to `layer`, as a build step: the partial model and its bricks' indexes
// in the whole.
Assembly up_to_layer(const Assembly& whole, int layer, std::vector<int>& whole_index) {
  Assembly partial;
  whole_index.clear();
  for (int i = 0; i < int(whole.bricks.size()); ++i)
    if (whole.bricks[size_t(i)].min.y <= layer * kBrick) {
      whole_index.push_back(i);
      partial.bricks.push_back(whole.bricks[size_t(i)]);
    }
  partial.ground_height = 0;
  return partial;
}

// Random stacks built layer by layer, each step begun from the forces (and the LP's spread) of
// the step before, as the building order does: every step that a certificate says stands has an
// exact C_M at least the certificate's.
TEST(Certificate, AStepsCertificateNeverExceedsItsExactCm) {
  constexpr int kLayers = 6;
  int certified = 0, checked = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const Assembly whole = random_stack(seed, kLayers);
    StepForces built;
    for (int layer = 0; layer < kLayers; ++layer) {
      std::vector<int> whole_index;
      const Assembly partial = up_to_layer(whole, layer, whole_index);
      const StepStability step = analyze_step(partial, whole_index, built, {}, 0.0);
      const StabilityResult exact = analyze_stability(partial);
      if (!step.forces.empty()) built = step.forces;
      ++checked;
      if (!step.result.certified) continue;
      ++certified;
      EXPECT_LE(step.result.cm_gf(), exact.cm_gf() + 1e-6) << "seed " << seed << " layer " << layer;
      EXPECT_GT(exact.cm_gf(), 0) << "seed " << seed << " layer " << layer;
      EXPECT_EQ(step.result.stable(), exact.stable()) << "seed " << seed << " layer " << layer;
    }
  }
  EXPECT_GT(certified, checked / 3) << "certified " << certified << " of " << checked;
}

// After a step the LP solved, the next steps are certified by its spread, near their exact C_M:
// the LP's optimum moved with the load as the LP would move it. Body by body, the same steps'
// bounds were far below (the duck at height 24: 1.3 gf where the LP gives 59.5).
TEST(Certificate, TheLpsSpreadCertifiesTheStepsAfterItNearTheirCm) {
  constexpr int kLayers = 7, kSolved = 2;
  int spread = 0, near = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const Assembly whole = random_stack(seed, kLayers);
    StepForces built;
    for (int layer = kSolved; layer < kLayers; ++layer) {
      std::vector<int> whole_index;
      const Assembly partial = up_to_layer(whole, layer, whole_index);
      // No certificate passes the first step's threshold: the LP solves it.
      const StepStability step =
          analyze_step(partial, whole_index, built, {}, layer == kSolved ? 1e9 : 0.0);
      const StabilityResult exact = analyze_stability(partial);
      if (!step.forces.empty()) built = step.forces;
      if (step.result.stats.solver != kSpreadCertificate) continue;
      ++spread;
      const std::string where = fmt::format("seed {} layer {}", seed, layer);
      EXPECT_LE(step.result.cm_gf(), exact.cm_gf() + 1e-6) << where;
      EXPECT_EQ(step.result.stable(), exact.stable()) << where;
      near += step.result.cm_gf() >= 0.95 * exact.cm_gf();
    }
  }
  EXPECT_GE(spread, 20);
  EXPECT_GE(near, spread * 9 / 10) << near << " of " << spread << " within 5% of their C_M";
}

// The weakest step is solved once whatever the bounds; again only while a few bounds lie below
// the smallest exact C_M, where the few solves left may settle which step is weakest.
TEST(StepStability, TheWeakestStepIsSolvedAgainOnlyWhereAFewBoundsAreBelowTheExact) {
  auto bounds = [](std::vector<double> certified, std::vector<double> exact) {
    std::vector<StepMargin> out;
    for (double cm : certified) out.push_back({cm, true});
    for (double cm : exact) out.push_back({cm, false});
    return out;
  };
  static_assert(kWeakestStepSolves == 3, "the cases below count three solves");
  const auto many = bounds({36, 37, 38, 39, 40}, {});
  EXPECT_TRUE(solve_weakest_again(many, 0));
  // One solve found 70 gf: four bounds below it, more than the solves could ever settle.
  EXPECT_FALSE(solve_weakest_again(bounds({37, 38, 39, 40, 71}, {70}), 1));
  // Three below it: the two solves left may find the weakest among them.
  EXPECT_TRUE(solve_weakest_again(bounds({37, 38, 39, 71, 72}, {70}), 1));
  EXPECT_TRUE(solve_weakest_again(bounds({37, 38, 71, 72}, {70, 71}), 2));
  // Bounds above the smallest exact C_M do not count; the solves are spent at three.
  EXPECT_TRUE(solve_weakest_again(bounds({65, 66, 67, 68}, {60}), 1));
  EXPECT_FALSE(solve_weakest_again(bounds({65}, {60, 61, 62}), 3));
}

// Asked for a bound, the certificate lowers its largest frictions by small LPs near them: never
// past the exact C_M, and higher than without on some of the random stacks below.
TEST(Certificate, AWantedBoundLowersTheLargestFrictions) {
  int higher = 0, found = 0;
  for (unsigned seed = 1; seed <= 24; ++seed) {
    const Assembly a = random_stack(seed, 7);
    StabilityResult r = analyze_contacts(a, {});
    const EquilibriumSystem sys = build_equilibrium(a, r, {});
    const Certificate plain = certify(sys, r.graph);
    const Certificate lowered = certify(sys, r.graph, {}, nullptr, kMaxFrictionLoad);
    solve_equilibrium(a, sys, {}, r);
    if (!plain.found) continue;
    ++found;
    ASSERT_TRUE(lowered.found) << "seed " << seed << ": " << lowered.why_not;
    EXPECT_GE(lowered.cm, plain.cm - 1e-9) << "seed " << seed;
    EXPECT_LE(lowered.cm / kGravity, r.cm_gf() + 1e-6) << "seed " << seed;
    higher += lowered.cm > plain.cm * (1 + 1e-3);
  }
  EXPECT_GE(found, 12);
  EXPECT_GE(higher, 3) << "of " << found;
}

}  // namespace
}  // namespace lego::physics
