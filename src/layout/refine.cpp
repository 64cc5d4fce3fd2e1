#include "layout/refine.h"

#include <chrono>
#include <limits>

#include "layout/components.h"
#include "layout/reconfigure.h"

namespace lego::layout {

double comparable_cm_gf(const physics::StabilityResult& r) {
  return r.status == physics::StabilityStatus::Solved ? r.cm_gf()
                                                      : -std::numeric_limits<double>::infinity();
}

namespace {

using Clock = std::chrono::steady_clock;

struct Analysis {
  physics::StabilityResult result;
  std::vector<int> critical;  // w_L^R as layout ids
};

// Algorithm 8 on the layout: C_M and the bottleneck's bricks (the pair with the largest share of
// the binding duals; the ground is not a brick). Without a bottleneck (no equilibrium at all),
// a random brick stands in for it.
Analysis analyze(const Layout& layout, const BrickCatalog& catalog, const RefineOptions& options,
                 Random& rng, RefineResult& totals) {
  const auto start = Clock::now();
  const LayoutAssembly la = to_assembly(layout, catalog, options.inside_color, options.loads);
  Analysis a;
  a.result = physics::analyze_stability(la.assembly, options.stability);
  totals.lp_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  ++totals.lp_solves;
  if (!a.result.weakest.empty()) {
    const physics::WeakContact& w = a.result.weakest.front();
    if (w.lower != physics::kGround) a.critical.push_back(la.layout_id[w.lower]);
    a.critical.push_back(la.layout_id[w.upper]);
  } else if (layout.brick_count() > 0) {
    a.critical.push_back(la.layout_id[rng.below(la.layout_id.size())]);
  }
  return a;
}

}  // namespace

RefineResult refine_layout(Layout& layout, const BrickCatalog& catalog, const MergeRules& rules,
                           Random& rng, const RefineOptions& options) {
  const auto start = Clock::now();
  RefineResult out;
  Analysis current = analyze(layout, catalog, options, rng, out);
  out.initial = current.result;
  double cm = comparable_cm_gf(current.result);
  int fails = 0;
  auto report = [&] {
    if (!options.progress) return;
    options.progress(
        RefineProgress{.iteration = out.iterations,
                       .accepted = out.accepted,
                       .fail_count = fails,
                       .lp_solves = out.lp_solves,
                       .cm_gf = cm,
                       .seconds = std::chrono::duration<double>(Clock::now() - start).count()});
  };
  while (!(cm > options.min_cm_gf) && fails < options.fail_max && !current.critical.empty()) {
    ++out.iterations;
    layout.begin_edit();
    reconfigure(layout, current.critical, ring_size(fails, options.ring_step), rules, rng);
    if (analyze_components(layout, rng, options.ground_connects).count != 1) {
      layout.rollback();
      ++fails;
      ++out.rejected_disconnected;
      report();
      continue;
    }
    Analysis candidate = analyze(layout, catalog, options, rng, out);
    const double candidate_cm = comparable_cm_gf(candidate.result);
    if (candidate_cm > cm) {
      layout.commit();
      current = std::move(candidate);
      cm = candidate_cm;
      fails = 0;
      ++out.accepted;
    } else {
      layout.rollback();
      ++fails;
    }
    report();
  }
  out.final = std::move(current.result);
  out.stable = cm > options.min_cm_gf;
  out.gave_up = !out.stable && fails >= options.fail_max;
  return out;
}

}  // namespace lego::layout
