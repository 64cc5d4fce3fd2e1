// The benchmark of issue 8: a fixed set of inputs through the stability engine and through the
// legolize pipeline, one line each, medians of --repeat runs. Columns are only ever added at the
// end, so runs can be compared line by line:
//   input voxels bricks rows cols nonzeros init_s refine_s iterations lp_solves solve_s
//   cm_before cm_after rejected_by_bound
// (solve_s: the median time of one whole-model stability analysis, for pipelines that of the
// final layout; lp_solves: whole-model analyses; rejected_by_bound: refinement candidates
// rejected on a local bound instead; "-" where a column does not apply).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <unordered_map>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "core/stopwatch.h"
#include "layout/build_order.h"
#include "layout/pieces.h"
#include "layout/reconfigure.h"
#include "layout/refine.h"
#include "mesh/mesh.h"
#include "physics/clp_lp.h"
#include "physics/step_stability.h"
#include "physics_bench.h"
#include "report/audit.h"
#include "shapes.h"
#include "voxel/palette.h"
#include "voxel/visibility.h"
#include "voxel/voxelize.h"

using namespace lego;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[v.size() / 2];
}

std::string number(double v, const char* format = "{:.3f}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string("-");
}

void header() {
  fmt::print(
      "{:<26} {:>11} {:>6} {:>7} {:>7} {:>8} {:>7} {:>8} {:>5} {:>5} {:>8} {:>9} {:>9} {:>6}\n",
      "input", "voxels", "bricks", "rows", "cols", "nonzeros", "init_s", "refine_s", "iter", "lps",
      "solve_s", "cm_before", "cm_after", "bound");
}

struct Line {
  std::string input, voxels = "-";
  size_t bricks = 0;
  physics::LpStats lp;
  double init = NAN, refine = NAN, solve = NAN, cm_before = NAN, cm_after = NAN;
  int iterations = -1, lp_solves = 0;
  int rejected_by_bound = -1;  // refinement candidates rejected on a local bound
};

void print(const Line& l) {
  auto count = [](int n) { return n < 0 ? std::string("-") : std::to_string(n); };
  fmt::print(
      "{:<26} {:>11} {:>6} {:>7} {:>7} {:>8} {:>7} {:>8} {:>5} {:>5} {:>8} {:>9} {:>9} {:>6}\n",
      l.input, l.voxels, l.bricks, l.lp.rows, l.lp.columns, l.lp.nonzeros, number(l.init),
      number(l.refine), count(l.iterations), l.lp_solves, number(l.solve), number(l.cm_before),
      number(l.cm_after), count(l.rejected_by_bound));
  std::fflush(stdout);
}

// The stability engine alone on a generated assembly.
void stability_line(const std::string& name, const Assembly& a, int repeat) {
  Line l;
  l.input = name;
  l.bricks = a.bricks.size();
  std::vector<double> solve;
  for (int k = 0; k < repeat; ++k) {
    const auto t = Clock::now();
    const physics::StabilityResult r = physics::analyze_stability(a);
    solve.push_back(seconds_since(t));
    l.lp = r.stats;
    l.cm_before = l.cm_after = r.status == physics::StabilityStatus::Solved ? r.cm_gf() : NAN;
    ++l.lp_solves;
  }
  l.solve = median(solve);
  print(l);
}

// The legolize pipeline from a voxel target: initialization (Algorithm 3) and refinement
// (Algorithm 7), each timed; the refinement is capped at max_refine seconds.
struct Refinement {
  double load_top = 0;                                  // grams on the top knobs
  double min_cm = 0;                                    // refine until C_M/g exceeds this
  int bound_ring = layout::RefineOptions{}.bound_ring;  // negative: no local bounds
};

void pipeline_line(const std::string& name, const layout::Target& target, int repeat,
                   double max_refine, const Refinement& refinement = {}) {
  Line l;
  l.input = name;
  l.voxels = fmt::format("{}x{}x{}", target.width, target.height, target.depth);
  std::vector<double> init, refine, per_solve;
  for (int k = 0; k < repeat; ++k) {
    layout::Layout lay(target);
    Random rng(1);
    layout::MergeRules rules;
    auto t = Clock::now();
    layout::ConnectOptions connect;
    connect.ground_connects = true;
    layout::initialize_layout(lay, rules, rng, connect);
    init.push_back(seconds_since(t));
    layout::RefineOptions options;
    options.ground_connects = true;
    options.loads.top_grams = refinement.load_top;
    options.min_cm_gf = refinement.min_cm;
    options.bound_ring = refinement.bound_ring;
    options.max_seconds = max_refine;
    t = Clock::now();
    const layout::RefineResult r =
        layout::refine_layout(lay, BrickCatalog::standard(), rules, rng, options);
    refine.push_back(seconds_since(t));
    // One whole-model analysis: that of the final layout.
    per_solve.push_back(r.final.stats.graph_seconds + r.final.stats.build_seconds +
                        r.final.stats.solve_seconds);
    l.bricks = lay.brick_count();
    l.lp = r.final.stats;
    l.iterations = r.iterations;
    l.lp_solves = r.lp_solves;
    l.rejected_by_bound = r.rejected_by_bound;
    l.cm_before = layout::comparable_cm_gf(r.initial);
    l.cm_after = layout::comparable_cm_gf(r.final);
  }
  l.init = median(init);
  l.refine = median(refine);
  l.solve = median(per_solve);
  print(l);
}

layout::Target from_mesh(const fs::path& file, const voxel::VoxelizeOptions& vo) {
  const mesh::Mesh m = mesh::load_mesh(file, {});
  voxel::VoxelGrid grid = voxel::voxelize(m, vo);
  voxel::hollow(grid, 3);
  return layout::target_from_voxels(grid, voxel::Palette::paper(ldraw::ColorTable::standard()));
}

// A shape given voxel by voxel, hollowed to a shell of 3 as legolize does: voxels next to an
// empty one are its surface (white), voxel::hollow keeps what lies within 3 of them.
layout::Target hollowed(int width, int height, int depth,
                        const std::function<bool(int, int, int)>& inside) {
  voxel::VoxelGrid g;
  g.width = width, g.height = height, g.depth = depth;
  g.cells.assign(size_t(width) * height * depth, voxel::Cell::Empty);
  g.color.assign(g.cells.size(), mesh::Rgb{1, 1, 1});
  for (int y = 0; y < height; ++y)
    for (int z = 0; z < depth; ++z)
      for (int x = 0; x < width; ++x)
        if (inside(x, y, z)) g.cells[g.index(x, y, z)] = voxel::Cell::Inside;
  std::vector<size_t> surface;
  for (int y = 0; y < height; ++y)
    for (int z = 0; z < depth; ++z)
      for (int x = 0; x < width; ++x) {
        if (g.at(x, y, z) == voxel::Cell::Empty) continue;
        for (auto [dx, dy, dz] :
             {std::array{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}})
          if (g.at(x + dx, y + dy, z + dz) == voxel::Cell::Empty) {
            surface.push_back(g.index(x, y, z));
            break;
          }
      }
  for (size_t i : surface) g.cells[i] = voxel::Cell::Surface;
  voxel::hollow(g, 3);
  return layout::target_from_voxels(g, voxel::Palette::paper(ldraw::ColorTable::standard()));
}

// The paper's TABLE at its size: a top two bricks thick over four legs, 95 x 50 x 95 voxels.
layout::Target paper_table() {
  return hollowed(95, 50, 95, [](int x, int y, int z) {
    const bool top = y >= 46;
    const bool leg = (x < 8 || x >= 87) && (z < 8 || z >= 87);
    return top || leg;
  });
}

// A teapot-like shape of 98 x 40 x 62 voxels: a squat body, a spout, a handle and a lid knob.
layout::Target teapot_like() {
  return hollowed(98, 40, 62, [](int x, int y, int z) {
    // Voxels are 1.2 studs tall: measure y in studs.
    const double yy = y * 1.2, dx = x - 49.0, dz = z - 31.0;
    const bool body =
        (dx * dx + dz * dz) / (30.0 * 30.0) + (yy - 20) * (yy - 20) / (21.0 * 21.0) <= 1;
    const bool knob = yy >= 40 && yy < 46 && dx * dx + dz * dz <= 25;
    // Spout: a tube rising from the body's side towards +x.
    const double s = (x - 75) / 20.0;
    const bool spout = s >= 0 && s <= 1 && std::hypot(yy - (14 + 24 * s), dz) <= 5 - 2 * s;
    // Handle: a ring in the x-y plane on the -x side.
    const bool handle =
        x < 22 && std::abs(dz) <= 2 && std::abs(std::hypot(x - 19.0, yy - 24) - 11) <= 2.5;
    return body || knob || spout || handle;
  });
}

// Audits every model of the corpus (../shared/ldraw-corpus/models.txt) with the shared parts
// library, one after the other, each with part knowledge derived afresh (as one brickcheck run
// pays it), and hands each to `visit` with the seconds it took (an unreadable file as
// Verdict::Unreadable). Returns false when there is no corpus.
bool for_each_corpus_model(
    const fs::path& shared, const report::AuditOptions& options,
    const std::function<void(const std::string&, const report::Audit&, double)>& visit) {
  std::ifstream list(shared / "ldraw-corpus" / "models.txt");
  if (!list) return false;
  for (std::string name; std::getline(list, name);) {
    if (name.empty()) continue;
    parts::PartLibrary knowledge(options.read.library_dirs, BrickCatalog::standard());
    const auto t = Clock::now();
    report::Audit a;
    try {
      a = report::audit_file(shared / "ldraw-corpus" / name, options, knowledge);
    } catch (const std::exception&) {
      a.verdict = report::Verdict::Unreadable;
    }
    visit(name, a, seconds_since(t));
  }
  return true;
}

report::AuditOptions corpus_options(const fs::path& shared, double max_seconds) {
  report::AuditOptions options;
  options.read.library_dirs = {shared / "ldraw-library"};
  options.stability.max_seconds = max_seconds;
  return options;
}

// legolize itself, as a user runs it, on meshes at its default height (issue 38: every sculpture
// stands, or says what it changed): its exit code, whether the model and every build step stand,
// the supports it added, C_M before and after, and the seconds of the refinement, the supports,
// the build order and the whole run (one run each: a run takes minutes).
void legolize_section(const std::vector<std::pair<std::string, fs::path>>& files) {
  fmt::print(
      "# legolize at its default height: input exit stable steps_stand support_columns "
      "support_bricks bricks cm_initial cm_final refine_s supports_s build_order_s "
      "total_s\n");
  const fs::path scratch = fs::temp_directory_path() / "legolization-bench-legolize";
  fs::create_directories(scratch);
  for (const auto& [name, file] : files) {
    if (!fs::exists(file)) continue;
    const fs::path out = scratch / (name + ".mpd"), report = scratch / (name + ".json");
    const std::string command =
        fmt::format("'{}' '{}' -o '{}' --report '{}' --quiet > /dev/null 2>&1", LEGOLIZE,
                    file.string(), out.string(), report.string());
    const int status = std::system(command.c_str());
    const int exit = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(report);
    if (!in) {
      fmt::print("{} {} - - - - - - - - - - -\n", name, exit);
      continue;
    }
    const nlohmann::json r = nlohmann::json::parse(in);
    std::map<std::string, double> seconds;
    for (const auto& [stage, s] : r["seconds"].items()) seconds[stage] = s.get<double>();
    auto number = [](const nlohmann::json& j) {
      return j.is_number() ? fmt::format("{:.3f}", j.get<double>()) : std::string("-");
    };
    fmt::print("{} {} {} {} {} {} {} {} {} {:.1f} {:.1f} {:.1f} {:.1f}\n", name, exit,
               r["stable"].get<bool>(),
               r["steps_stand"].is_boolean() && r["steps_stand"].get<bool>(),
               r["supports"]["columns"].get<int>(), r["supports"]["bricks"].get<int>(),
               r["bricks"].get<int>(), number(r["cm_gf_initial"]), number(r["cm_gf_final"]),
               seconds["refine"], seconds["supports"], seconds["build_order"], seconds["total"]);
  }
}

// What a command cost: its exit code, wall seconds and peak memory (of the largest child).
struct Run {
  int exit = -1;
  double seconds = NAN, max_rss_mb = NAN;
};

Run run_command(const std::vector<std::string>& argv, const fs::path& out) {
  const auto start = Clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_WRONLY);
    if (fd < 0 || null < 0) _exit(127);
    dup2(fd, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  Run r;
  int status = 0;
  struct rusage usage {};
  if (pid < 0 || wait4(pid, &status, 0, &usage) != pid) return r;
  r.seconds = seconds_since(start);
  r.exit = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.max_rss_mb = double(usage.ru_maxrss) / 1024;
  return r;
}

// brickcheck on towns of the corpus's models (issue 37: a whole town), as a user runs it on one
// file: placed parts, wall seconds, peak memory, the time and memory per part, the time per part
// over the smallest town's, the verdict and the report's stage times. The towns are made once by
// tools/bench/make_town.py in the bench's scratch folder and kept there for later runs.
void town_section(const fs::path& source, const fs::path& shared, bool quick) {
  const fs::path corpus = shared / "ldraw-corpus" / "models.txt";
  const fs::path library = shared / "ldraw-library";
  if (!fs::exists(corpus) || !fs::exists(library)) return;
  const fs::path scratch = fs::temp_directory_path() / "legolization-bench-town";
  fs::create_directories(scratch);
  fmt::print(
      "\n# brickcheck on a town: parts placed wall_s max_rss_mb us_per_part kb_per_part "
      "per_part_over_smallest verdict parse_s parts_s graph_s solve_s\n");
  double smallest = NAN;
  for (int thousands : quick ? std::vector<int>{10, 30} : std::vector<int>{10, 30, 100, 300}) {
    const fs::path town = scratch / fmt::format("town-{}k.mpd", thousands);
    if (!fs::exists(town)) {
      const std::string make = fmt::format(
          "python3 '{}' --parts {} --ldraw-dir '{}' --part-info '{}' -o '{}' '{}' > /dev/null",
          (source / "tools" / "bench" / "make_town.py").string(), thousands * 1000,
          library.string(), PART_INFO, town.string(), corpus.string());
      if (std::system(make.c_str()) != 0) {
        fmt::print("town-{}k: make_town.py failed\n", thousands);
        continue;
      }
    }
    const fs::path report = scratch / fmt::format("town-{}k.json", thousands);
    const Run run = run_command({BRICKCHECK, "--json", "--max-seconds", "1800", "--ldraw-dir",
                                 library.string(), town.string()},
                                report);
    std::ifstream in(report);
    nlohmann::json r;
    try {
      r = nlohmann::json::parse(in);
    } catch (const std::exception&) {
      fmt::print("town-{}k: exit {}, no report\n", thousands, run.exit);
      continue;
    }
    const double parts = r["parts"].get<double>();
    const double per_part = run.seconds / parts;
    if (!std::isfinite(smallest)) smallest = per_part;
    auto stage = [&](const char* name) {
      return number(r["timing"][name].get<double>(), "{:.1f}");
    };
    fmt::print("town-{}k {} {:.1f} {:.0f} {:.0f} {:.1f} {:.2f} {} {} {} {} {}\n", thousands, parts,
               run.seconds, run.max_rss_mb, per_part * 1e6, run.max_rss_mb * 1024 / parts,
               per_part / smallest, r["verdict"].get<std::string>(), stage("parse"), stage("parts"),
               stage("graph"), stage("solve"));
  }
  // Many files at once: the corpus's models with -j 2 against one after another, in one run.
  std::vector<std::string> files;
  std::ifstream list(corpus);
  for (std::string name; std::getline(list, name);)
    if (!name.empty() && name[0] != '#') files.push_back((corpus.parent_path() / name).string());
  std::map<int, Run> by_jobs;
  for (int jobs : {1, 2}) {
    std::vector<std::string> argv{BRICKCHECK,           "--json",      "-j",
                                  std::to_string(jobs), "--ldraw-dir", library.string()};
    argv.insert(argv.end(), files.begin(), files.end());
    by_jobs[jobs] = run_command(argv, scratch / fmt::format("corpus-j{}.json", jobs));
  }
  fmt::print("corpus of {} models: -j 1 {:.1f} s, -j 2 {:.1f} s, ratio {:.2f}\n", files.size(),
             by_jobs[1].seconds, by_jobs[2].seconds, by_jobs[2].seconds / by_jobs[1].seconds);
}

// brickcheck over the Datsville corpus: the share of models with a C_M, of part occurrences
// analysed, carried and left out, the models with floating parts, time per model, and the
// reasons parts are carried.
void corpus_section(const fs::path& shared, double max_seconds) {
  const fs::path corpus = shared / "ldraw-corpus", library = shared / "ldraw-library";
  int models = 0, with_cm = 0, floating = 0, unreadable = 0, judged = 0, assuming = 0;
  size_t parts = 0, analysed = 0, turned = 0, carried = 0, left_out = 0;
  double analysed_mass = 0, carried_mass = 0;
  std::vector<double> times;
  std::string slowest;
  std::map<std::string, int> reasons;
  auto count = [&](const std::string& name, const report::Audit& a, double seconds) {
    ++models;
    times.push_back(seconds);
    if (times.back() >= *std::max_element(times.begin(), times.end())) slowest = name;
    if (a.verdict == report::Verdict::Unreadable) {
      ++unreadable;
      return;
    }
    with_cm += a.stability.status == physics::StabilityStatus::Solved;
    floating += !a.stability.connectivity.all_grounded();
    judged +=
        a.verdict != report::Verdict::NotJudged && a.verdict != report::Verdict::NothingToAnalyse;
    assuming += a.verdict == report::Verdict::Stable && !a.assumptions.summary().empty();
    analysed_mass += a.assumptions.analysed_mass_g;
    carried_mass += a.assumptions.carried_mass_g;
    parts += a.model.parts.size();
    analysed += a.conversion.assembly.bricks.size();
    turned += size_t(report::turned_lattice_bricks(a.conversion.assembly));
    carried += a.conversion.assembly.carried.size();
    left_out += a.conversion.skipped.size();
    for (const auto& c : a.conversion.assembly.carried)
      ++reasons[std::string(carried_because(c.role))];
  };
  for_each_corpus_model(shared, corpus_options(shared, max_seconds), count);
  if (models == 0) return;
  auto share = [](double n, double of) { return fmt::format("{:.1f}%", 100 * n / of); };
  fmt::print("\ncorpus: {} models of {} with {}\n", models, (corpus / "models.txt").string(),
             library.string());
  fmt::print("{:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>9}  slowest\n", "with_cm", "analysed",
             "carried", "left_out", "floating", "unreadable", "median_s", "max_s");
  fmt::print("{:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>9}  {}\n", share(with_cm, models),
             share(double(analysed), double(parts)), share(double(carried), double(parts)),
             share(double(left_out), double(parts)), share(floating, models), unreadable,
             number(median(times)), number(*std::max_element(times.begin(), times.end())), slowest);
  fmt::print("analysed on turned lattices: {} occurrences ({})\n", turned,
             share(double(turned), double(parts)));
  fmt::print(
      "judged: {} of the models; stable with assumptions: {}; mass analysed: {} of what is "
      "analysed or carried\n",
      share(judged, models), share(assuming, models),
      share(analysed_mass, analysed_mass + carried_mass));
  std::vector<std::pair<int, std::string>> ranked;
  for (const auto& [reason, n] : reasons) ranked.emplace_back(n, reason);
  std::sort(ranked.rbegin(), ranked.rend());
  fmt::print("why parts are carried ({} occurrences):\n", carried);
  for (const auto& [n, reason] : ranked) fmt::print("{:>7}  {}\n", n, reason);
}

// The corpus's heat maps (issue 17), as `brickcheck --heatmap` computes them: the models whose
// map needs a QP (a C_M below T), how many of those maps fall back to the analysis's forces, and
// the map's time against its analysis (both analyses where there are two): the median, the models
// over twice (the target), and all maps together.
void corpus_heat_section(const fs::path& shared, double max_seconds) {
  report::AuditOptions options = corpus_options(shared, max_seconds);
  options.brick_capacity = true;
  int maps = 0, fallbacks = 0, over_twice = 0;
  double map_seconds = 0, analysis_seconds = 0, worst_ratio = 0;
  std::vector<double> ratios;
  std::string worst;
  auto count = [&](const std::string& name, const report::Audit& a, double) {
    const physics::LpStats& stats = a.stability.stats;
    if (stats.capacity_solver.empty()) return;
    ++maps;
    fallbacks += stats.capacity_solver != std::string("interior point");
    const double ratio = stats.capacity_seconds / std::max(stats.solve_seconds, 1e-9);
    ratios.push_back(ratio);
    over_twice += ratio > 2;
    map_seconds += stats.capacity_seconds;
    analysis_seconds += stats.solve_seconds;
    if (ratio > worst_ratio) worst_ratio = ratio, worst = name;
  };
  const bool ran = for_each_corpus_model(shared, options, count);
  if (!ran || maps == 0) return;
  fmt::print("\ncorpus heat maps: per-brick capacity of the models that need friction\n");
  fmt::print("{:>6} {:>9} {:>9} {:>10} {:>8} {:>10}  worst\n", "maps", "fallback", "x_median",
             "over_2x", "map_s", "analysis_s");
  fmt::print("{:>6} {:>9} {:>9} {:>10} {:>8} {:>10}  {} ({:.1f}x)\n", maps, fallbacks,
             fmt::format("{:.2f}", median(ratios)), over_twice, number(map_seconds, "{:.1f}"),
             number(analysis_seconds, "{:.1f}"), worst, worst_ratio);
}

// legolize's layout of a target, initialized and refined as legolize does, with `top_grams` on
// its top: the assembly (the load in it), the options it was refined with, and its height.
struct RefinedLayout {
  Assembly assembly;
  layout::RefineOptions options;
  int height = 0;
};
RefinedLayout refined_layout(const layout::Target& target, double top_grams) {
  layout::Layout lay(target);
  Random rng(1);
  layout::MergeRules rules;
  layout::ConnectOptions connect;
  connect.ground_connects = true;
  layout::initialize_layout(lay, rules, rng, connect);
  RefinedLayout out;
  out.options.ground_connects = true;
  out.options.loads.top_grams = top_grams;
  layout::refine_layout(lay, BrickCatalog::standard(), rules, rng, out.options);
  out.assembly = layout::to_assembly(lay, BrickCatalog::standard(), 72, out.options.loads).assembly;
  out.height = lay.height();
  return out;
}

// Steps whose forces only grow (issue 36, by name: `--only monotone`, `--only monotone-duck`):
// each step's model balanced by the step before's forces plus increments that add to pushes and
// frictions and lower none, the largest friction least (one LP of the increments per step, by
// Clp's simplex: minutes, not a timing). Such forces stay valid for every step before (a sum of
// increments that each balance their own step's new weight), so one bound covers them all. Beside
// it, each step's exact C_M (the same LP, forces free to fall) and the build order's value.
void monotone_steps_section(const std::vector<std::pair<std::string, layout::Target>>& targets) {
  using physics::ForceKind;
  fmt::print("\nbuild steps whose forces only grow: the bound they keep against each step's C_M\n");
  fmt::print("{:<12} {:>5} {:>6} {:>9} {:>9} {:>9} {:>5} {:>7}\n", "input", "step", "bricks",
             "exact", "monotone", "order", "cert", "lp_s");
  for (const auto& [name, target] : targets) {
    const RefinedLayout refined = refined_layout(target, 0);
    const Assembly& a = refined.assembly;
    const physics::StabilityOptions& stability = refined.options.stability;
    layout::BuildOrderOptions order_options;
    order_options.stability = stability;
    const layout::BuildOrder order = layout::plan_build_order(a, order_options);
    // Forces by column key (physics::StepSystem): the monotone ones so far.
    std::unordered_map<uint64_t, double> grown;
    for (size_t k = 0; k < order.steps.size(); ++k) {
      Assembly partial;
      partial.ground_height = a.ground_height;
      std::vector<int> whole_index;
      for (size_t i = 0; i < a.bricks.size(); ++i)
        if (order.step_of[i] <= int(k) + 1) {
          partial.bricks.push_back(a.bricks[i]);
          whole_index.push_back(int(i));
        }
      const physics::StepSystem step = physics::prepare_step(partial, whole_index, stability);
      const physics::EquilibriumSystem& sys = step.system;
      if (sys.rows == 0) continue;
      // max t: A·(x + dx) = b, x + dx within the bounds, every friction ≤ T − t; with `grow`,
      // dx ≥ 0 on pushes and frictions. C_M (gf) the forces x + dx keep, into `forces`.
      auto least_friction = [&](std::unordered_map<uint64_t, double>& forces, bool grow) {
        constexpr double inf = std::numeric_limits<double>::infinity();
        std::vector<double> x(size_t(sys.columns()), 0.0);
        for (int j = 0; j < sys.columns(); ++j)
          if (const auto it = forces.find(step.column_keys[size_t(j)]); it != forces.end())
            x[size_t(j)] = it->second;
        const std::vector<double> unbalanced = sys.unbalanced(x);
        physics::LpData lp;
        lp.rows = sys.rows + sys.friction_columns;  // the friction columns come first
        std::vector<std::pair<int, double>> entries;
        for (int j = 0; j < sys.columns(); ++j) {
          entries.clear();
          for (int e = sys.column_start[size_t(j)]; e < sys.column_start[size_t(j) + 1]; ++e)
            entries.emplace_back(sys.row_index[size_t(e)], sys.value[size_t(e)]);
          const double lower = grow ? 0.0 : -x[size_t(j)];
          if (sys.kind[size_t(j)] == ForceKind::Friction) {
            entries.emplace_back(sys.rows + j, 1.0);
            lp.add_column(lower, physics::kMaxFrictionLoad - x[size_t(j)], 0.0, entries);
          } else {
            lp.add_column(sys.kind[size_t(j)] == ForceKind::Normal ? lower : -inf, inf, 0.0,
                          entries);
          }
        }
        entries.clear();
        for (int j = 0; j < sys.friction_columns; ++j) entries.emplace_back(sys.rows + j, -1.0);
        lp.add_column(0.0, physics::kMaxFrictionLoad, 1.0, entries);  // the largest friction
        for (int r = 0; r < sys.rows; ++r) {
          lp.row_lower.push_back(unbalanced[size_t(r)]);
          lp.row_upper.push_back(unbalanced[size_t(r)]);
        }
        for (int j = 0; j < sys.friction_columns; ++j) {
          lp.row_lower.push_back(-inf);
          lp.row_upper.push_back(-x[size_t(j)]);
        }
        const physics::LpSolution s =
            physics::solve_lp(lp, physics::LpMethod::DualSimplex, true, true, 600);
        if (s.outcome != physics::LpOutcome::Optimal) return -inf;
        for (int j = 0; j < sys.columns(); ++j)
          forces[step.column_keys[size_t(j)]] = x[size_t(j)] + s.x[size_t(j)];
        return (physics::kMaxFrictionLoad - s.x.back()) / kGravity;
      };
      const auto t = Clock::now();
      const double monotone = least_friction(grown, true);
      const double lp_s = seconds_since(t);
      std::unordered_map<uint64_t, double> none;
      const double exact = least_friction(none, false);
      fmt::print("{:<12} {:>5} {:>6} {:>9} {:>9} {:>9} {:>5} {:>7}\n", name, k + 1,
                 partial.bricks.size(), number(exact), number(monotone),
                 number(order.steps[k].cm_gf), order.steps[k].certified ? "yes" : "no",
                 number(lp_s, "{:.2f}"));
      std::fflush(stdout);
    }
  }
}

// Build steps (issue 16): legolize's layout of each mesh (initialized and refined, as legolize
// does), its layers taken as steps the way legolize wrote them before the building order, and
// the building order (layout/build_order.h): the steps that stand in each, the smallest step C_M,
// the time the order takes against one analysis of the finished model, the most new bricks in
// one step (target 30) and the steps a certificate showed standing.
void steps_section(const std::vector<std::pair<std::string, layout::Target>>& targets,
                   const std::vector<double>& loads) {
  fmt::print("\nbuild steps: layer steps as written before, then the building order\n");
  fmt::print(
      "{:<26} {:>6} {:>6} {:>11} {:>6} {:>11} {:>6} {:>9} {:>9} {:>4} {:>7} {:>9} {:>7} {:>9} "
      "{:>7} {:>9}\n",
      "input", "bricks", "layers", "layer_stand", "steps", "steps_stand", "held", "min_cm",
      "order_s", "lps", "lp_s", "final_s", "ratio", "ratio_cert", "max_new", "certified");
  for (size_t k = 0; k < targets.size(); ++k) {
    const auto& [name, target] = targets[k];
    const RefinedLayout refined = refined_layout(target, loads[k]);
    const Assembly& a = refined.assembly;
    const layout::RefineOptions& options = refined.options;
    auto t = Clock::now();
    physics::analyze_stability(a, options.stability);
    const double final_s = seconds_since(t);
    // Layer steps: everything up to a layer, without loads (a load is the finished model's).
    int layers = 0, layers_stand = 0;
    for (int top = 0; top < refined.height; ++top) {
      Assembly partial;
      partial.ground_height = a.ground_height;
      for (const Brick& b : a.bricks)
        if (b.min.y <= top * kPlatesPerBrick) partial.bricks.push_back(b);
      if (partial.bricks.empty()) continue;
      ++layers;
      layers_stand += physics::analyze_stability(partial, options.stability).stable();
    }
    Assembly unloaded = a;
    unloaded.loads.clear();
    layout::BuildOrderOptions order_options;
    order_options.stability = options.stability;
    t = Clock::now();
    const layout::BuildOrder order = layout::plan_build_order(unloaded, order_options);
    const double order_s = seconds_since(t);
    int stand = 0, max_new = 0;
    for (const auto& st : order.steps) {
      stand += st.stands;
      max_new = std::max(max_new, st.new_bricks);
    }
    // ratio_cert: the steps' cost without their LPs (the certificates and the rest), against
    // the final analysis.
    fmt::print(
        "{:<26} {:>6} {:>6} {:>11} {:>6} {:>11} {:>6} {:>9} {:>9} {:>4} {:>7} {:>9} {:>7} {:>9} "
        "{:>7} {:>9}\n",
        name, a.bricks.size(), layers, fmt::format("{}/{}", layers_stand, layers),
        order.steps.size(), fmt::format("{}/{}", stand, order.steps.size()), order.held_back,
        number(order.min_cm_gf()), number(order_s), order.lp_solves, number(order.lp_seconds),
        number(final_s), fmt::format("{:.1f}", order_s / final_s),
        fmt::format("{:.1f}", (order_s - order.lp_seconds) / final_s), max_new,
        fmt::format("{}/{}", order.certified_steps(), order.steps.size()));
    std::fflush(stdout);
  }
}

// legolize's fidelity on real meshes (issue 18), per mesh at one height: the share of visible
// voxels whose brick colour is within CIEDE2000 10 of the surface colour (current palette, and
// the paper's eight for comparison), the objects in the air and the columns under them, the
// pieces (objects off the ground built apart, none once they stand on columns), the
// layout's parts before and after joining thin parts with the voxels added, and inside (IGNORE)
// voxels seen from outside before colour_seen_inside and in the finished layout (target 0).
void meshes_section(const std::vector<std::pair<std::string, fs::path>>& files, int height) {
  fmt::print("\nmeshes at {} bricks high: colour fidelity, pieces, joining, IGNORE seen\n", height);
  fmt::print("{:<22} {:>7} {:>8} {:>7} {:>7} {:>6} {:>8} {:>13} {:>6} {:>11} {:>10} {:>8} {:>6}\n",
             "input", "voxels", "visible", "de10", "de10_pp", "pieces", "in_air", "parts_bef_aft",
             "added", "ignore_seen", "ignore_now", "warnings", "secs");
  const auto& table = ldraw::ColorTable::standard();
  for (const auto& [name, file] : files) {
    if (!fs::exists(file)) continue;
    const auto t = Clock::now();
    const mesh::Mesh m = mesh::load_mesh(
        file, {.up = {}, .default_color = voxel::from_hex(*table.rgb(71)), .guard_seconds = 0});
    voxel::VoxelGrid grid = voxel::voxelize(m, {.height_bricks = height});
    voxel::hollow(grid, 3);
    auto seen_inside = [&](const voxel::VoxelGrid& g) {
      size_t n = 0;
      for (size_t i : voxel::seen_from_outside(g.width, g.height, g.depth, [&](size_t c) {
             return g.cells[c] != voxel::Cell::Empty;
           }))
        n += g.cells[i] == voxel::Cell::Inside;
      return n;
    };
    const size_t ignore_before = seen_inside(grid);
    voxel::colour_seen_inside(grid);
    const voxel::Palette current = voxel::Palette::current(table).with(71, table);
    const voxel::Palette paper = voxel::Palette::paper(table).with(71, table);
    const std::vector<size_t> visible =
        voxel::seen_from_outside(grid.width, grid.height, grid.depth,
                                 [&](size_t c) { return grid.cells[c] != voxel::Cell::Empty; });
    // The layout in the current palette: its bricks' colours at the visible voxels.
    // As legolize: what is in the air stands on columns, then the pieces.
    layout::Target target = layout::target_from_voxels(grid, current);
    const layout::FloatingSupports floating = layout::stand_floating_objects(target);
    std::vector<layout::Piece> pieces = layout::split_pieces(target);
    std::vector<int> brick_color(target.color.size(), layout::kEmpty);
    int before = 0, after = 0;
    size_t added = 0;
    Random rng(1);
    for (layout::Piece& p : pieces) {
      layout::ConnectOptions connect;
      connect.ground_connects = true;
      const int lift = p.lift;
      layout::JoinedLayout j =
          layout::initialize_joined(std::move(p.target), layout::MergeRules{}, rng, connect);
      before += j.pieces_before;
      after += j.connect.components;
      added += j.voxels_added;
      const layout::Layout& lay = *j.layout;
      for (size_t i = 0; i < target.color.size(); ++i) {
        const int x = int(i % size_t(target.width)),
                  y = int(i / (size_t(target.width) * target.depth)),
                  z = int((i / size_t(target.width)) % size_t(target.depth));
        if (y < lift) continue;
        if (const int b = lay.brick_at(x, y - lift, z); b >= 0 && target.color[i] != layout::kEmpty)
          brick_color[i] = lay.brick(b).color;
      }
    }
    size_t close = 0, close_paper = 0, ignore_now = 0;
    for (size_t i : visible) {
      const voxel::Lab surface = voxel::to_lab(grid.color[i]);
      const int c = brick_color[i];
      if (c == layout::kIgnore) ++ignore_now;
      const int code = c == layout::kIgnore ? 72 : c;
      if (code >= 0 &&
          voxel::ciede2000(surface, voxel::to_lab(voxel::from_hex(*table.rgb(code)))) <= 10)
        ++close;
      const int best_paper = paper.nearest(grid.color[i]);
      if (voxel::ciede2000(surface, voxel::to_lab(voxel::from_hex(*table.rgb(best_paper)))) <= 10)
        ++close_paper;
    }
    const double n = double(std::max<size_t>(visible.size(), 1));
    fmt::print(
        "{:<22} {:>7} {:>8} {:>6.1f}% {:>6.1f}% {:>6} {:>8} {:>13} {:>6} {:>11} {:>10} {:>8} "
        "{:>6.1f}\n",
        name, target.filled(), visible.size(), 100.0 * close / n, 100.0 * close_paper / n,
        pieces.size(), fmt::format("{}/{}", floating.objects, floating.columns),
        fmt::format("{} -> {}", before, after), added, ignore_before, ignore_now, m.warnings.size(),
        seconds_since(t));
    std::fflush(stdout);
  }
}

// The stability solver on irregular models (issue 17), per case: bricks, our interior point
// method's iterations, time and solver path (with Clp taking over when it fails), C_M, Clp's
// dual simplex on the same model in the same run (time, capped at a minute; C_M; ratio), a
// regular model of the same size (a hollow box: time and the case's ratio to it; target at most
// 3), and the heat map's per-brick capacity (time and its ratio to the analysis, target at most
// 2, "*" after it when our method failed and the map shows the analysis's own forces; then its
// QP's iterations, the last column since c352183).
void hard_line(const std::string& name, const Assembly& a) {
  auto timed = [&](const physics::StabilityOptions& o) {
    const auto t = Clock::now();
    physics::StabilityResult r = physics::analyze_stability(a, o);
    return std::pair{std::move(r), seconds_since(t)};
  };
  auto cm = [](const physics::StabilityResult& r) {
    return r.status == physics::StabilityStatus::Solved ? number(r.cm_gf())
                                                        : std::string(physics::to_string(r.status));
  };
  const auto [ipm, ipm_s] = timed({});
  // Clp's dual simplex gets a minute: on solid blocks it takes many (over 5 at 2,017 bricks).
  physics::StabilityOptions clp_options;
  clp_options.method = physics::LpMethod::DualSimplex;
  clp_options.max_seconds = 60;
  const auto [clp, clp_s] = timed(clp_options);
  const bool clp_done = clp.status != physics::StabilityStatus::IterationLimit;
  const Assembly regular = bench::hollow_box_of(int(a.bricks.size()));
  const auto [reg, reg_s] = timed({});
  std::string capacity = "-", capacity_ratio = "-", capacity_iterations = "-";
  if (ipm.status == physics::StabilityStatus::Solved) {
    physics::StabilityOptions o;
    o.brick_capacity = true;
    o.max_seconds = 600;
    const auto [with, with_s] = timed(o);
    capacity = number(with.stats.capacity_seconds, "{:.2f}") +
               (with.stats.capacity_solver == "interior point" ? "" : "*");
    capacity_ratio = fmt::format("{:.1f}", with.stats.capacity_seconds / ipm_s);
    capacity_iterations = std::to_string(with.stats.capacity_iterations);
  }
  fmt::print(
      "{:<24} {:>6} {:>5} {:>8} {:<34} {:>9} {:>8} {:>9} {:>6} {:>8} {:>6} {:>8} {:>6} {:>7}\n",
      name, a.bricks.size(), ipm.stats.iterations, number(ipm_s, "{:.2f}"),
      ipm.stats.solver.empty() ? std::string("-") : ipm.stats.solver, cm(ipm),
      (clp_done ? "" : ">") + number(clp_s, "{:.2f}"), clp_done ? cm(clp) : "-",
      fmt::format("{}{:.2f}", clp_done ? "" : "<", ipm_s / clp_s), number(reg_s, "{:.2f}"),
      fmt::format("{:.1f}", ipm_s / reg_s), capacity, capacity_ratio, capacity_iterations);
  if (!ipm.message.empty()) fmt::print("    ({})\n", ipm.message);
  std::fflush(stdout);
}

void hard_section(const fs::path& spider, const std::string& only, bool quick) {
  fmt::print("\nhard cases for the stability solver (ours vs Clp's dual simplex, same run)\n");
  fmt::print(
      "{:<24} {:>6} {:>5} {:>8} {:<34} {:>9} {:>8} {:>9} {:>6} {:>8} {:>6} {:>8} {:>6} {:>7}\n",
      "input", "bricks", "iter", "ipm_s", "solver", "cm", "clp_s", "clp_cm", "x_clp", "box_s",
      "x_box", "heat_s", "x_heat", "heat_it");
  auto wanted = [&](const std::string& name) {
    return only.empty() || only == "hard" || name.find(only) != std::string::npos;
  };
  // Solid running-bond towers of 16 x 16 studs (a wall as thick as the tower is wide).
  for (int layers : quick ? std::vector<int>{63} : std::vector<int>{63, 250}) {
    const Assembly a = bench::hollow_box(16, 16, layers, 8);
    const std::string name = fmt::format("solid-tower-{}", a.bricks.size());
    if (wanted(name)) hard_line(name, a);
  }
  // A solid block of about 20,000 bricks: only when asked for by name (minutes).
  if (only.find("solid-block") != std::string::npos)
    hard_line("solid-block-20000", bench::hollow_box(40, 40, 100, 20));
  // A model with duplicated parts: three bricks of a 342-brick box placed twice.
  if (wanted("duplicated-parts")) {
    Assembly a = bench::hollow_box_of(342);
    for (size_t k : {size_t(10), a.bricks.size() / 2, a.bricks.size() - 5})
      a.bricks.push_back(a.bricks[k]);
    hard_line("duplicated-parts", a);
  }
  // A 1-stud-wide cantilever, 24 studs out from a 2x2 column, in running bond over two layers,
  // with 200 g at its tip.
  if (wanted("cantilever")) {
    const auto& catalog = BrickCatalog::standard();
    Assembly a;
    auto put = [&](const char* part, int x, int layer, bool rotated) {
      Brick b;
      b.type = catalog.find(part);
      b.rotated = rotated;
      b.min = {x, 3 * layer, 0};
      b.color = 15;
      a.bricks.push_back(b);
      return int(a.bricks.size()) - 1;
    };
    for (int layer = 0; layer < 6; ++layer) put("3003", 0, layer, false);
    int tip = -1;
    for (int layer = 6; layer < 8; ++layer)
      for (int x = layer % 2 * 2; x < 26; x += 4) tip = put("3010", x, layer, false);
    a.loads.push_back({.brick = tip,
                       .force_n = {0, -weight_newton(200), 0},
                       .spread_over_top_knobs = true,
                       .point = {0, 0, 0}});
    hard_line("cantilever-24+200g", a);
  }
  // legolize's layouts of Assimp's spider at 20 bricks, seeds 1-5 (initialization with thin
  // parts joined; no refinement).
  if (fs::exists(spider)) {
    const mesh::Mesh m =
        mesh::load_mesh(spider, {.up = {}, .default_color = {}, .guard_seconds = 0});
    voxel::VoxelGrid grid = voxel::voxelize(m, {.height_bricks = 20});
    voxel::hollow(grid, 3);
    voxel::colour_seen_inside(grid);
    const auto& table = ldraw::ColorTable::standard();
    const layout::Target target =
        layout::target_from_voxels(grid, voxel::Palette::current(table).with(71, table));
    for (uint64_t seed = 1; seed <= (quick ? 1u : 5u); ++seed) {
      const std::string name = fmt::format("spider-h20-seed{}", seed);
      if (!wanted(name)) continue;
      Random rng(seed);
      layout::ConnectOptions connect;
      connect.ground_connects = true;
      const layout::JoinedLayout j = layout::initialize_joined(target, {}, rng, connect);
      hard_line(name, layout::to_assembly(*j.layout, BrickCatalog::standard(), 72).assembly);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"legolization benchmark (issue 8): stability engine and legolize pipeline"};
  bool quick = false;
  int repeat = 3;
  double max_refine = 600;
  std::string only;
  app.add_flag("--quick", quick, "a short run: small inputs, one repetition");
  app.add_option("--repeat", repeat, "runs per input; medians are printed (default 3)");
  app.add_option("--max-refine-seconds", max_refine, "cap on one refinement (default 600)");
  app.add_option("--only", only, "run only inputs whose name contains this");
  CLI11_PARSE(app, argc, argv);
  if (quick) repeat = 1;
  const fs::path source = LEGOLIZATION_SOURCE_DIR;
  const fs::path bunny = source / ".." / "shared" / "meshes" / "bunny.obj";
  auto wanted = [&](const std::string& name) {
    return only.empty() || name.find(only) != std::string::npos;
  };

  header();
  std::vector<int> sizes =
      quick ? std::vector<int>{500, 2000} : std::vector<int>{500, 2000, 8000, 20000};
  for (int n : sizes)
    if (wanted(fmt::format("box-{}", n)))
      stability_line(fmt::format("box-{}", n), bench::hollow_box_of(n), repeat);
  for (int n : quick ? std::vector<int>{500} : std::vector<int>{500, 2000})
    if (wanted(fmt::format("tower-{}", n)))
      stability_line(fmt::format("tower-{}", n), bench::hollow_box(10, 10, n / 8), repeat);

  struct Mesh {
    std::string name;
    fs::path file;
    voxel::VoxelizeOptions options;
    Refinement refinement;
    int repeat = 0;  // 0: --repeat
  };
  std::vector<Mesh> meshes{
      {"sample-table+300g", source / "samples" / "table.obj", {.mm_per_unit = 1}, {300}, 0},
      {"sample-globe-h16", source / "samples" / "globe.ply", {.height_bricks = 16}, {}, 0},
      {"sample-crate-h8", source / "samples" / "crate.obj", {.height_bricks = 8}, {}, 0},
  };
  if (fs::exists(bunny)) {
    // 30 bricks high stands in for the paper's TAILS (32 x 30 x 46 voxels, 1,642 bricks).
    for (int h : quick ? std::vector<int>{20} : std::vector<int>{20, 30, 40, 60})
      meshes.push_back({fmt::format("bunny-h{}", h), bunny, {.height_bricks = h}, {}, 0});
  }
  if (!quick) {
    // A refinement of a thousand bricks, with and without the local bounds, in one run: the
    // table at twice its size with 8 kg on top, refined towards 65 gf (it stops at fail_MAX).
    const Refinement heavy{.load_top = 8000, .min_cm = 65};
    meshes.push_back(
        {"table-x2+8kg-cm65", source / "samples" / "table.obj", {.mm_per_unit = 2}, heavy, 1});
    Refinement unbounded = heavy;
    unbounded.bound_ring = -1;
    meshes.push_back({"table-x2+8kg-cm65-nobounds",
                      source / "samples" / "table.obj",
                      {.mm_per_unit = 2},
                      unbounded,
                      1});
  }
  for (const auto& m : meshes)
    if (wanted(m.name))
      pipeline_line(m.name, from_mesh(m.file, m.options), m.repeat > 0 ? m.repeat : repeat,
                    max_refine, m.refinement);
  if (!quick) {
    if (wanted("table-95x50x95")) pipeline_line("table-95x50x95", paper_table(), 1, max_refine);
    if (wanted("teapot-98x40x62")) pipeline_line("teapot-98x40x62", teapot_like(), 1, max_refine);
  }
  if (wanted("steps")) {
    std::vector<std::pair<std::string, layout::Target>> targets;
    std::vector<double> loads;
    auto add = [&](const std::string& name, const fs::path& file, voxel::VoxelizeOptions vo,
                   double load = 0) {
      if (!fs::exists(file)) return;
      targets.emplace_back(name, from_mesh(file, vo));
      loads.push_back(load);
    };
    add("steps-table+300g", source / "samples" / "table.obj", {.mm_per_unit = 1}, 300);
    add("steps-globe-h16", source / "samples" / "globe.ply", {.height_bricks = 16});
    add("steps-crate-h8", source / "samples" / "crate.obj", {.height_bricks = 8});
    add("steps-bunny-h20", bunny, {.height_bricks = 20});
    if (!quick) add("steps-bunny-h30", bunny, {.height_bricks = 30});
    // Debian's assimp-testmodels, where installed.
    const fs::path assimp = "/usr/share/assimp/models";
    add("steps-duck-h20", assimp / "Collada" / "duck.dae", {.height_bricks = 20});
    // The spider's thin legs: its layout is not stable yet (the refinement gives up after
    // minutes), so neither can its steps be; in the full run only.
    if (!quick) add("steps-spider-h20", assimp / "OBJ" / "spider.obj", {.height_bricks = 20});
    add("steps-human-h20", assimp / "BLEND" / "HUMAN.blend", {.height_bricks = 20});
    steps_section(targets, loads);
  }
  if (only.rfind("monotone", 0) == 0) {  // minutes: only when asked for by name
    const fs::path duck = "/usr/share/assimp/models/Collada/duck.dae";
    if (only == "monotone-duck" && fs::exists(duck))
      monotone_steps_section({{"duck-h20", from_mesh(duck, {.height_bricks = 20})}});
    else
      monotone_steps_section(
          {{"globe-h16", from_mesh(source / "samples" / "globe.ply", {.height_bricks = 16})}});
  }
  if (wanted("meshes")) {
    const fs::path assimp = "/usr/share/assimp/models";
    std::vector<std::pair<std::string, fs::path>> files{
        {"sample-globe", source / "samples" / "globe.ply"},
        {"sample-crate", source / "samples" / "crate.obj"},
        {"bunny", bunny},
        {"earth", assimp / "Collada" / "earthCylindrical.DAE"},
        {"teapots", assimp / "Collada" / "teapots.DAE"},
        {"duck", assimp / "Collada" / "duck.dae"},
        {"spider", assimp / "OBJ" / "spider.obj"},
        {"human", assimp / "BLEND" / "HUMAN.blend"},
        {"box-gltf-textured", assimp / "glTF2" / "BoxTextured-glTF" / "BoxTextured.gltf"},
        {"cubes-fbx", assimp / "FBX" / "cubes_with_names.fbx"},
        {"engine-glb", assimp / "glTF2" / "2CylinderEngine-glTF-Binary" / "2CylinderEngine.glb"},
        {"wuson-stl", assimp / "STL" / "Wuson.stl"},
        {"sphere-hole-stl", assimp / "STL" / "sphereWithHole.stl"},
        {"fels-3ds", assimp / "3DS" / "fels.3ds"},
    };
    meshes_section(files, quick ? 16 : 24);
  }
  // Only when asked for by name (`--only legolize`, or `--only legolize-duck` for one): ten runs
  // of minutes each.
  if (only.rfind("legolize", 0) == 0) {
    const fs::path assimp = "/usr/share/assimp/models";
    std::vector<std::pair<std::string, fs::path>> files{
        {"bunny", bunny},
        {"spider-obj", assimp / "OBJ" / "spider.obj"},
        {"spider-fbx", assimp / "FBX" / "spider.fbx"},
        {"milk-truck-gltf", assimp / "glTF" / "CesiumMilkTruck" / "CesiumMilkTruck.gltf"},
        {"duck", assimp / "Collada" / "duck.dae"},
        {"teapots", assimp / "Collada" / "teapots.DAE"},
        {"earth", assimp / "Collada" / "earthCylindrical.DAE"},
        {"engine-glb", assimp / "glTF2" / "2CylinderEngine-glTF-Binary" / "2CylinderEngine.glb"},
        {"human", assimp / "BLEND" / "HUMAN.blend"},
        {"wuson-stl", assimp / "STL" / "Wuson.stl"},
    };
    std::erase_if(files, [&](const auto& f) { return !wanted("legolize-" + f.first); });
    legolize_section(files);
  }
  if (wanted("hard") || only.find("solid") != std::string::npos ||
      only.find("spider-h20") != std::string::npos || only == "duplicated-parts" ||
      only == "cantilever")
    hard_section("/usr/share/assimp/models/OBJ/spider.obj", only, quick);
  if (wanted("physics")) bench::physics_section(source, source / ".." / "shared");
  if (wanted("corpus")) corpus_section(source / ".." / "shared", 60);
  // Minutes of runs: only when asked for by name.
  if (only == "town") town_section(source, source / ".." / "shared", quick);
  // Heat maps double the corpus's time: only in a whole run or when asked for by name.
  if (only.empty() || only == "corpus-heat") corpus_heat_section(source / ".." / "shared", 60);
}
