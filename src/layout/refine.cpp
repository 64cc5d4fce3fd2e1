#include "layout/refine.h"

#include <array>
#include <chrono>
#include <limits>
#include <thread>

#include "core/stopwatch.h"
#include "layout/components.h"
#include "layout/reconfigure.h"
#include "physics/local_bounds.h"

namespace lego::layout {

double comparable_cm_gf(const physics::StabilityResult& r) {
  return r.status == physics::StabilityStatus::Solved && r.connectivity.all_grounded()
             ? r.cm_gf()
             : -std::numeric_limits<double>::infinity();
}

namespace {

using Clock = std::chrono::steady_clock;

// C_M gains smaller than this (grams-force) are within the analysis' accuracy, not progress.
constexpr double kMeaningfulGain = 1e-4;

// A local bound over more of the model than this costs about what the whole analysis does and
// may not decide: such candidates go straight to the whole analysis. On the table sample at
// twice its size (1,162 bricks) bounds over regions of half the model still rejected 99 of 119
// candidates and cut the refinement from 124 s to 67 s.
constexpr double kMaxBoundRegionShare = 0.75;

// The bottleneck's bricks by voxel, so it can be found again after an edit is replayed.
struct Analysis {
  physics::StabilityResult result;
  std::vector<std::array<int, 3>> critical;  // w_L^R: voxels of its bricks
};

// Algorithm 8 on an assembly of a layout: C_M and the bottleneck's bricks (the pair with the
// largest share of the binding duals; the ground is not a brick), by voxel. Without a bottleneck
// (no equilibrium at all), a random brick stands in for it. Reads only the assembly, so
// candidates can be analysed on threads of their own.
Analysis analyze(const Assembly& assembly, int grid_depth, const RefineOptions& options,
                 size_t random_pick) {
  Analysis a;
  a.result = physics::analyze_stability(assembly, options.stability);
  auto voxel_of = [&](int brick) {  // to_assembly's mapping backwards (lattice z is flipped)
    const Brick& b = assembly.bricks[size_t(brick)];
    return std::array{b.min.x, b.min.y / kPlatesPerBrick, grid_depth - b.max_z()};
  };
  const auto& w = a.result.weakest;
  if (!w.empty()) {
    if (w.front().lower != physics::kGround) a.critical.push_back(voxel_of(w.front().lower));
    a.critical.push_back(voxel_of(w.front().upper));
  } else if (!assembly.bricks.empty()) {
    a.critical.push_back(voxel_of(int(random_pick % assembly.bricks.size())));
  }
  return a;
}

std::vector<int> critical_ids(const Layout& layout, const Analysis& a) {
  std::vector<int> ids;
  for (const auto& v : a.critical) ids.push_back(layout.brick_at(v[0], v[1], v[2]));
  return ids;
}

// One candidate of a round: the edit that makes it and, once analysed, its analysis.
struct Candidate {
  Edit edit;
  LayoutAssembly assembly;
  Analysis analysis;
  size_t random_pick = 0;
  bool connected = false;
  bool ruled_out = false;  // its local upper bound does not beat the current C_M
  double bound_seconds = 0;
};

// A round of `count` candidates, made one after another on the layout, each undone after it is
// recorded, so every candidate starts from the current layout (Algorithm 7's reconfiguration).
std::vector<Candidate> make_round(Layout& layout, const BrickCatalog& catalog,
                                  const MergeRules& rules, Random& rng,
                                  const RefineOptions& options, const std::vector<int>& critical,
                                  int fails, size_t count, RefineResult& out) {
  std::vector<Candidate> round(count);
  for (size_t c = 0; c < round.size(); ++c) {
    ++out.iterations;
    layout.begin_edit();
    reconfigure(layout, critical, ring_size(fails + int(c), options.ring_step), rules, rng);
    round[c].random_pick = size_t(rng.next());
    round[c].connected = analyze_components(layout, rng, options.ground_connects).count == 1;
    if (round[c].connected) {
      round[c].edit = layout.open_edit();
      round[c].assembly =
          to_assembly(layout, catalog, options.inside_color, options.loads, options.support_color);
    } else {
      ++out.rejected_disconnected;
    }
    layout.rollback();
  }
  return round;
}

// The round's connected candidates analysed at the same time (`side_by_side`), each on its own
// assembly; first the local upper bound, which rules out most candidates for the cost of a small
// LP. A candidate ruled out counts as not connected from here on: it cannot be chosen.
void analyse_round(std::vector<Candidate>& round, const Assembly& current_assembly,
                   const Analysis& current, double cm, int depth, const RefineOptions& options,
                   bool side_by_side, RefineResult& out) {
  auto analyse = [&](Candidate& c) {
    if (options.bound_ring >= 0) {
      const physics::CmBounds bounds =
          physics::bound_cm_locally(current_assembly, current.result, c.assembly.assembly,
                                    {.ring = options.bound_ring,
                                     .max_region_share = kMaxBoundRegionShare,
                                     .lower = false,
                                     .stability = options.stability});
      c.bound_seconds = bounds.seconds;
      c.ruled_out = bounds.valid && bounds.upper_gf() <= cm + kMeaningfulGain;
      if (c.ruled_out) return;
    }
    c.analysis = analyze(c.assembly.assembly, depth, options, c.random_pick);
  };
  std::vector<std::thread> threads;
  for (size_t c = 1; c < round.size(); ++c)
    if (round[c].connected) {
      if (side_by_side)
        threads.emplace_back(analyse, std::ref(round[c]));
      else
        analyse(round[c]);
    }
  if (round[0].connected) analyse(round[0]);
  for (auto& th : threads) th.join();
  for (Candidate& c : round) {
    if (!c.connected) continue;
    out.bound_seconds += c.bound_seconds;
    if (c.ruled_out) {
      c.connected = false;
      ++out.rejected_by_bound;
    } else {
      ++out.lp_solves;
    }
  }
}

// The best candidate that beats C_M `cm` by more than the analysis' accuracy (C_M to 1e-6
// relative; smaller gains are noise); the earliest among those within that accuracy of the best,
// so last-bit differences never choose. -1: none.
int best_of(const std::vector<Candidate>& round, double cm) {
  double top = -std::numeric_limits<double>::infinity();
  for (const Candidate& c : round)
    if (c.connected) top = std::max(top, comparable_cm_gf(c.analysis.result));
  int best = -1;
  for (size_t c = 0; c < round.size() && best < 0; ++c) {
    const double candidate_cm =
        round[c].connected ? comparable_cm_gf(round[c].analysis.result) : top - 1;
    if (candidate_cm > cm + kMeaningfulGain && candidate_cm > top - kMeaningfulGain) best = int(c);
  }
  return best;
}

}  // namespace

RefineResult refine_layout(Layout& layout, const BrickCatalog& catalog, const MergeRules& rules,
                           Random& rng, const RefineOptions& options) {
  const auto start = Clock::now();
  RefineResult out;
  Assembly current_assembly;  // of the layout as it stands, whose analysis `current` is
  Analysis current = [&] {
    current_assembly =
        to_assembly(layout, catalog, options.inside_color, options.loads, options.support_color)
            .assembly;
    Analysis a = analyze(current_assembly, layout.depth(), options, size_t(rng.next()));
    ++out.lp_solves;
    return a;
  }();
  out.initial = current.result;
  double cm = comparable_cm_gf(current.result);
  int fails = 0;
  auto report = [&] {
    if (!options.progress) return;
    options.progress(RefineProgress{.iteration = out.iterations,
                                    .accepted = out.accepted,
                                    .fail_count = fails,
                                    .lp_solves = out.lp_solves,
                                    .cm_gf = cm,
                                    .seconds = seconds_since(start)});
  };
  const int per_round = std::max(1, options.candidates_per_round);
  const bool side_by_side = options.side_by_side && per_round > 1;
  while (!(cm > options.min_cm_gf) && fails < options.fail_max && !current.critical.empty()) {
    if (seconds_since(start) > options.max_seconds) {
      out.out_of_time = true;
      break;
    }
    std::vector<Candidate> round =
        make_round(layout, catalog, rules, rng, options, critical_ids(layout, current), fails,
                   size_t(std::min(per_round, options.fail_max - fails)), out);
    analyse_round(round, current_assembly, current, cm, layout.depth(), options, side_by_side, out);
    const int best = best_of(round, cm);
    const double best_cm = best >= 0 ? comparable_cm_gf(round[size_t(best)].analysis.result) : cm;
    if (best >= 0) {
      layout.begin_edit();
      layout.apply(round[size_t(best)].edit);
      layout.commit();
      current = std::move(round[size_t(best)].analysis);
      current_assembly = std::move(round[size_t(best)].assembly.assembly);
      cm = best_cm;
      fails = 0;
      ++out.accepted;
    } else {
      fails += int(round.size());
    }
    report();
  }
  out.final = std::move(current.result);
  out.stable = cm > options.min_cm_gf;
  out.gave_up = !out.stable && fails >= options.fail_max;
  return out;
}

}  // namespace lego::layout
