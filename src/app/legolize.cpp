// legolize: a colored mesh to a LEGO model that stands (paper Algorithm 1): voxels with LEGO
// proportions, a maximal single-connected brick layout, stability-aware refinement, and LDraw
// files whose build steps each stand (layout/build_order.h), with instructions on request.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include "app/legolize_options.h"
#include "app/number_checks.h"
#include "app/output_paths.h"
#include "core/brick_catalog.h"
#include "core/error.h"
#include "core/lattice.h"
#include "core/memory.h"
#include "core/stop.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "layout/build_order.h"
#include "layout/pieces.h"
#include "layout/reconfigure.h"
#include "layout/refine.h"
#include "layout/supports.h"
#include "layout/to_assembly.h"
#include "layout/where_on_model.h"
#include "ldraw/reader.h"
#include "ldraw/writer.h"
#include "mesh/mesh.h"
#include "physics/force_model.h"
#include "report/conversion_report.h"
#include "report/instructions.h"
#include "report/parts_list.h"
#include "report/render.h"
#include "voxel/palette.h"
#include "voxel/voxelize.h"

using namespace lego;
namespace fs = std::filesystem;

namespace {

constexpr int kInsideColor = 72;  // Dark Bluish Grey: voxels whose color does not matter (IGNORE)
constexpr int kUncolouredColor = 71;  // Light Bluish Grey: surfaces the mesh gives no colour
constexpr int kExitUnstable = 1, kExitBadInput = 2, kExitUndecided = 4;

using Clock = std::chrono::steady_clock;

voxel::Palette parse_palette(const std::string& spec) {
  const auto& table = ldraw::ColorTable::standard();
  if (spec == "current") return voxel::Palette::current(table);
  if (spec == "paper") return voxel::Palette::paper(table);
  if (spec == "all") return voxel::Palette::all(table);
  std::vector<int> codes;
  std::stringstream in(spec);
  for (std::string item; std::getline(in, item, ',');) {
    auto code = ldraw::parse_color_code(item);
    if (!code) throw InputError("", 0, "--palette: '" + item + "' is not an LDraw colour code");
    codes.push_back(*code);
  }
  return voxel::Palette::of(codes, table);
}

std::array<int, 3> parse_size(const std::string& size) {
  std::array<int, 3> fit{0, 0, 0};
  char x1 = 0, x2 = 0, extra = 0;
  std::istringstream in(size);
  if (!(in >> fit[0] >> x1 >> fit[1] >> x2 >> fit[2]) || (x1 != 'x' && x1 != 'X') ||
      (x2 != 'x' && x2 != 'X') || (in >> extra) || fit[0] < 1 || fit[1] < 1 || fit[2] < 1)
    throw InputError("", 0, "--size '" + size + "': expected WxHxD, three positive whole numbers");
  return fit;
}

// "X,Y,Z:GRAMS": a weight on the brick at voxel (X, Y, Z), Y counting layers from the bottom.
layout::VoxelLoad parse_load(const std::string& spec) {
  layout::VoxelLoad load;
  char c1 = 0, c2 = 0, colon = 0, extra = 0;
  std::istringstream in(spec);
  if (!(in >> load.x >> c1 >> load.y >> c2 >> load.z >> colon >> load.grams) || c1 != ',' ||
      c2 != ',' || colon != ':' || (in >> extra) || !(load.grams >= 0) ||
      !std::isfinite(load.grams))
    throw InputError("", 0, "--load '" + spec + "': expected X,Y,Z:GRAMS (a voxel and a weight)");
  if (load.grams > physics::kMaxLoadGrams)
    throw InputError("", 0,
                     fmt::format("--load '{}': the weight must be at most {:.0f} grams (a tonne)",
                                 spec, physics::kMaxLoadGrams));
  return load;
}

std::string cm_words(double cm_gf) {
  return std::isfinite(cm_gf) ? fmt::format("{:.3f} gf", cm_gf) : std::string("no equilibrium");
}

// The verdict of an analysis in the words brickcheck uses: its C_M, "no equilibrium", or
// UNDECIDED when the solver gave up.
std::string analysis_words(const physics::StabilityResult& r) {
  if (!physics::decided(r.status))
    return fmt::format("UNDECIDED (the solver gave up: {})",
                       r.message.empty() ? physics::to_string(r.status) : r.message);
  return cm_words(layout::comparable_cm_gf(r));
}

std::string report_json(const report::ConversionReport& rep) {
  // A file name that is not UTF-8 (a Latin-1 "café.obj") is written with U+FFFD in its place.
  return to_json(rep).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// "heat.ldr" -> "heat-piece-2.ldr": the file of a model's further piece.
fs::path piece_file(const fs::path& path, int piece) {
  return path.parent_path() /
         fmt::format("{}-piece-{}{}", path.stem().string(), piece, path.extension().string());
}

struct PieceResult;
// A brick of a piece as a builder finds it on the model (layout/where_on_model.h), in words.
std::string describe_brick(const PieceResult& piece, int brick);
// Without its step: while the order is planned, the piece's order is not yet that of its bricks.
report::NamedBrick named_brick(const PieceResult& piece, int brick);

// Rounds of supports for build steps that fall, each followed by a new build order.
constexpr int kStepSupportRounds = 3;

// How every piece is converted: the options the user gave, shared by all pieces.
struct PieceSettings {
  const BrickCatalog* catalog = nullptr;
  layout::MergeRules* rules = nullptr;  // its limits are used up piece by piece
  layout::ColorTrades trades;           // what the refinement may trade (--color-trade)
  layout::RefineOptions refine;
  layout::ConnectOptions connect;
  layout::BuildOrderOptions order;
  layout::SupportOptions supports;
  bool refine_layout = true;
  bool add_supports = true;
  double min_cm = 0;
  std::function<void(const std::string&)> stage;
};

// One piece of the model (layout/pieces.h), from its voxels to an assembly whose build steps
// stand: layout initialization with thin parts joined (Algorithm 3), stability-aware refinement
// (Algorithm 7) and the build order.
struct PieceResult {
  int lift = 0, objects = 0;
  bool grounded() const { return lift == 0; }
  size_t voxels = 0;
  std::optional<layout::Layout> lay;
  layout::LayoutAssembly la;
  layout::ConnectResult connect;
  int pieces_before = 0;
  size_t voxels_added = 0;
  layout::RefineResult refined;  // `final` is the finished piece's analysis (with its supports)
  layout::SupportResult supports;
  size_t support_bricks = 0;
  layout::ColorChanges colours;  // of the finished layout against its voxels
  bool stable = true, steps_stand = true;
  std::string bottleneck;
  std::vector<report::NamedBrick> bottleneck_bricks;  // the bricks `bottleneck` names
  layout::BuildOrder order;
  double seconds_initialize = 0, seconds_refine = 0, seconds_supports = 0, seconds_order = 0;
};

// Layout initialization with thin parts joined (Algorithm 3): out.lay, and out.bottleneck where
// no single connected layout was found.
void lay_out(layout::Piece& piece, Random& rng, const PieceSettings& s,
             const layout::MergeRules& trading, PieceResult& out) {
  const auto t = Clock::now();
  layout::JoinedLayout joined =
      layout::initialize_joined(std::move(piece.target), trading, rng, s.connect);
  out.lay = std::move(joined.layout);
  layout::Layout& lay = *out.lay;
  out.connect = joined.connect;
  out.pieces_before = joined.pieces_before;
  out.voxels_added = joined.voxels_added;
  if (auto exceeded = s.rules->limits.exceeded(lay); !exceeded.empty()) {
    std::string words;
    for (const auto& e : exceeded) words += "\n  " + e;
    throw InputError("", 0, "impossible limits: the model needs more bricks than allowed:" + words);
  }
  out.seconds_initialize = seconds_since(t);
  s.stage(fmt::format("initialized: {} bricks, {} component{} ({} at first{})", lay.brick_count(),
                      out.connect.components, out.connect.components == 1 ? "" : "s",
                      out.pieces_before,
                      out.voxels_added ? fmt::format("; {} voxels added to join thin parts in {} "
                                                     "rounds",
                                                     out.voxels_added, joined.rounds)
                                       : std::string()));
  if (!out.connect.single) {
    out.stable = false;
    out.bottleneck = fmt::format(
        "no single connected layout after {} failed tries: {} parts that no brick joins",
        s.refine.fail_max, out.connect.components);
  }
}

// Stability-aware refinement (Algorithm 7), then supports under what still hangs and a second
// refinement around them. Whether the piece was refined at all.
bool refine_and_support(Random& rng, const PieceSettings& s, const layout::MergeRules& trading,
                        PieceResult& out) {
  layout::Layout& lay = *out.lay;
  auto t = Clock::now();
  const bool refining = out.connect.single && s.refine_layout;
  if (refining) {
    s.stage("refining");
    // With supports to come, the refinement takes half its time first; the rest goes to refining
    // again around the supports, where what still fails is local.
    layout::RefineOptions first = s.refine;
    if (s.add_supports) first.max_seconds = s.refine.max_seconds / 2;
    out.refined = layout::refine_layout(lay, *s.catalog, trading, rng, first);
    out.stable = out.refined.stable;
    s.stage(fmt::format(
        "refined: C_M {} -> {}, {} iterations, {} accepted; {} whole-model analyses, {} "
        "candidates rejected on local bounds ({:.2f} s)",
        analysis_words(out.refined.initial), analysis_words(out.refined.final),
        out.refined.iterations, out.refined.accepted, out.refined.lp_solves,
        out.refined.rejected_by_bound, out.refined.bound_seconds));
  }
  out.seconds_refine = seconds_since(t);
  // What the refinement could not make stand gets supports (layout/supports.h).
  if (refining && !out.stable && s.add_supports) {
    t = Clock::now();
    s.stage("adding supports under what hangs");
    out.supports = layout::add_supports(lay, *s.catalog, out.refined.final, s.supports);
    if (!out.supports.columns.empty()) {
      out.refined.final = out.supports.final;
      out.stable = out.supports.stable;
    }
    s.stage(
        fmt::format("columns: {} inside the hollow ({} voxels), {} support{} ({} voxels), C_M "
                    "{}; {} analyses ({:.2f} s){}",
                    out.supports.inside_columns(), out.supports.inside_voxels,
                    out.supports.support_columns(), out.supports.support_columns() == 1 ? "" : "s",
                    out.supports.voxels, analysis_words(out.refined.final), out.supports.analyses,
                    seconds_since(t), out.supports.out_of_time ? ", out of time" : ""));
    out.seconds_supports = seconds_since(t);
    if (!out.stable && !out.supports.columns.empty() && out.seconds_refine < s.refine.max_seconds) {
      t = Clock::now();
      s.stage("refining again, on the supports");
      layout::RefineOptions again = s.refine;
      again.max_seconds = s.refine.max_seconds - out.seconds_refine;
      const layout::RefineResult second =
          layout::refine_layout(lay, *s.catalog, trading, rng, again);
      out.refined.final = second.final;
      out.refined.iterations += second.iterations;
      out.refined.accepted += second.accepted;
      out.refined.lp_solves += second.lp_solves;
      out.refined.rejected_by_bound += second.rejected_by_bound;
      out.refined.out_of_time = second.out_of_time;
      out.refined.gave_up = second.gave_up;
      out.refined.stable = out.stable = second.stable;
      out.seconds_refine += seconds_since(t);
      s.stage(fmt::format("refined again: C_M {} -> {}, {} iterations ({:.2f} s)",
                          analysis_words(second.initial), analysis_words(second.final),
                          second.iterations, seconds_since(t)));
    }
  }
  return refining;
}

// The piece's layout as an assembly (out.la), its support bricks counted.
void assemble(const PieceSettings& s, PieceResult& out) {
  out.la = layout::to_assembly(*out.lay, *s.catalog, s.refine.inside_color, s.refine.loads,
                               s.refine.support_color);
  out.support_bricks = 0;
  for (const Brick& b : out.la.assembly.bricks) out.support_bricks += b.support;
}

// A building order in which every step stands (the paper's first limitation), with supports under
// steps that fall. When the last stage of it began.
Clock::time_point order_with_step_supports(const PieceSettings& s, bool refining,
                                           PieceResult& out) {
  layout::Layout& lay = *out.lay;
  auto t = Clock::now();
  layout::BuildOrderOptions order = s.order;
  order.describe = [&out](int brick) { return describe_brick(out, brick); };
  out.order = layout::plan_build_order(out.la.assembly, order);
  // A step that falls gets supports too: columns under its weak place, judged on that step, and
  // the order planned again. The finished model only gains by them.
  for (int round = 0; round < kStepSupportRounds && refining && s.add_supports && s.order.analyse &&
                      !out.order.all_stand();
       ++round) {
    t = Clock::now();
    const auto falls = std::find_if(out.order.steps.begin(), out.order.steps.end(),
                                    [](const layout::BuildStep& st) { return !st.stands; });
    const int k = int(falls - out.order.steps.begin()) + 1;
    layout::PlacedBricks step;
    step.placed.assign(lay.id_limit(), 0);
    for (size_t i = 0; i < out.la.assembly.bricks.size(); ++i)
      if (out.order.step_of[i] <= k) step.placed[size_t(out.la.layout_id[i])] = 1;
    s.stage(fmt::format("adding supports under step {}, which falls", k));
    const layout::SupportResult added = layout::add_supports(lay, *s.catalog, s.supports, step);
    s.stage(fmt::format("supports under step {}: {} column{} ({:.2f} s)", k, added.columns.size(),
                        added.columns.size() == 1 ? "" : "s", seconds_since(t)));
    if (added.columns.empty()) break;
    out.supports.columns.insert(out.supports.columns.end(), added.columns.begin(),
                                added.columns.end());
    out.supports.voxels += added.voxels;
    out.supports.inside_voxels += added.inside_voxels;
    out.supports.analyses += added.analyses;
    assemble(s, out);
    out.refined.final = physics::analyze_stability(out.la.assembly, s.refine.stability);
    out.stable = out.refined.final.stable(s.min_cm);
    out.seconds_supports += seconds_since(t);
    out.order = layout::plan_build_order(out.la.assembly, order);
  }
  return t;
}

// Where the finished piece fails, as a builder finds it: the bricks, where they are on the model
// and the steps that place them (and their voxels, as --load takes them, in `named`).
std::string bottleneck_words(const PieceResult& out, std::vector<report::NamedBrick>& named) {
  const auto& f = out.refined.final;
  auto placed = [&](int brick) {
    if (brick < 0) return describe_brick(out, brick);
    named.push_back(named_brick(out, brick));
    named.back().step = out.order.step_of[size_t(brick)];
    return fmt::format("{} (step {})", named.back().words(), named.back().step);
  };
  if (!f.weakest.empty()) {
    const std::string lower = placed(f.weakest.front().lower);
    return lower + " holding " + placed(f.weakest.front().upper);
  }
  if (!f.unbalanced.empty()) {
    std::vector<std::string> shown;
    for (size_t k = 0; k < std::min<size_t>(f.unbalanced.size(), 3); ++k)
      shown.push_back(placed(f.unbalanced[k]));
    return named_few(shown, f.unbalanced.size()) + ": no forces hold " +
           (f.unbalanced.size() == 1 ? "it" : "them") + " up (tipping or hanging)";
  }
  return physics::to_string(f.status);
}

PieceResult convert_piece(layout::Piece& piece, Random& rng, const PieceSettings& s) {
  PieceResult out;
  out.lift = piece.lift;
  out.objects = piece.objects;
  out.voxels = piece.voxels;
  // Colours are traded only where the layout breaks apart or does not stand (--color-trade).
  layout::MergeRules trading = *s.rules;
  trading.trades = s.trades;
  lay_out(piece, rng, s, trading, out);
  const bool refining = refine_and_support(rng, s, trading, out);
  assemble(s, out);
  if (!refining) {
    out.refined.initial = out.refined.final =
        physics::analyze_stability(out.la.assembly, s.refine.stability);
    out.stable = out.stable && out.refined.final.stable(s.min_cm);
  }
  const auto t = order_with_step_supports(s, refining, out);
  // What this piece uses is not there for the next (after the refinement and the supports,
  // which may change it).
  s.rules->limits.use_up(*out.lay);
  if (!out.stable && out.bottleneck.empty())
    out.bottleneck = bottleneck_words(out, out.bottleneck_bricks);
  const std::vector<int> moved = layout::apply_build_order(out.la.assembly, out.order);
  std::vector<int> layout_id(moved.size());
  for (size_t k = 0; k < moved.size(); ++k) layout_id[k] = out.la.layout_id[size_t(moved[k])];
  out.la.layout_id = std::move(layout_id);
  out.steps_stand = !s.order.analyse || out.order.all_stand();
  out.seconds_order = seconds_since(t);
  s.stage(s.order.analyse
              ? fmt::format("build order: {} steps, {}; smallest step C_M {}; {} analyses, {} "
                            "steps certified without the LP, {:.2f} s",
                            out.order.steps.size(),
                            out.steps_stand ? "every one stands" : "NOT every one stands",
                            (out.order.weakest_is_a_bound() ? "at least " : "") +
                                cm_words(out.order.min_cm_gf()),
                            out.order.analyses, out.order.certified_steps(), out.order.seconds)
              : fmt::format("build order: {} steps, not analysed", out.order.steps.size()));
  out.colours = layout::color_changes(*out.lay);
  // Where the piece was lowered from: its bricks go back there in the model.
  out.la.assembly.origin_ldu[1] -= out.lift * kPlatesPerBrick * kLduPerPlate;
  return out;
}

report::NamedBrick named_brick(const PieceResult& p, int brick) {
  const Brick& b = p.la.assembly.bricks[size_t(brick)];
  const layout::LayoutBrick& lb = p.lay->brick(p.la.layout_id[size_t(brick)]);
  return {.part = b.type->part,
          .name = readable_part_name(b.type->name),
          .where = layout::where_on_model(p.la.assembly, brick),
          .voxel = {lb.x, lb.y + p.lift, lb.z}};
}

std::string describe_brick(const PieceResult& p, int brick) {
  if (brick == physics::kGround) return "the ground";
  return named_brick(p, brick).words();
}

// A run of legolize: its options, its clock and progress lines, and the report it fills.
struct Run {
  const app::LegolizeOptions& o;
  Clock::time_point start = Clock::now();
  report::ConversionReport rep;

  explicit Run(const app::LegolizeOptions& options) : o(options) {
    rep.input = o.input;
    rep.output = o.output;
    rep.seed = o.seed;
    rep.version = LEGOLIZATION_VERSION;
    rep.min_cm_gf = o.min_cm;
  }
  void stage(const std::string& words) const {
    {
      const std::lock_guard lock(last_stage_mutex);
      last_stage = words;
    }
    if (!o.quiet)
      std::cerr << fmt::format("legolize [{:7.2f} s] {}\n", seconds_since(start), words);
  }
  // Where the run is (from any thread: the stop's says where --max-seconds ended it), and what
  // is written.
  std::string where() const {
    const std::lock_guard lock(last_stage_mutex);
    return fmt::format(
        "the run was at: {}; {}", last_stage,
        written ? "the outputs were written, the booklet was not" : "nothing was written");
  }
  std::atomic<bool> written{false};  // the outputs are in place

  std::function<void(const std::string&)> stage_sink() const {
    return [this](const std::string& words) { stage(words); };
  }

 private:
  mutable std::mutex last_stage_mutex;
  mutable std::string last_stage = "the start";
};

// What the options ask for, checked before the work starts: everything the user typed.
struct Plan {
  mesh::MeshOptions mesh;
  voxel::Palette palette;
  layout::MergeRules rules;
  layout::RefineOptions refine;
  voxel::VoxelizeOptions voxelize;
};

// The RGB of a colour an option names; a code the table lacks (or 16, 24) is refused.
unsigned solid_colour(const char* option, int code) {
  const auto rgb = ldraw::ColorTable::standard().rgb(code);
  if (!rgb || code == ldraw::kMainColor || code == ldraw::kEdgeColor)
    throw InputError("", 0, fmt::format("{}: {} is not in the colour table", option, code));
  return *rgb;
}

// A wanted list naming a colour BrickLink does not have is refused: say so before any work, for
// every colour of the palette (and the interior's and the supports', -1 for none) at once.
void check_bricklink_colours(const voxel::Palette& palette, int support_color) {
  const auto& map = report::BrickLinkMap::standard();
  const auto& table = ldraw::ColorTable::standard();
  std::vector<int> codes = palette.codes();
  codes.push_back(kInsideColor);
  if (support_color >= 0) codes.push_back(support_color);
  std::string missing;
  for (int code : codes)
    if (!map.color(code))
      missing += fmt::format("{}{} ({})", missing.empty() ? "" : ", ", code, table.name(code));
  if (!missing.empty())
    throw InputError("", 0,
                     fmt::format("--bricklink: no BrickLink colour for {} in the map "
                                 "(ldraw_parts/bricklink.csv); choose other --palette colours, "
                                 "or leave out --bricklink",
                                 missing));
}

// Colours outside --palette current are on the wanted list as asked, with a word on why they may
// be hard to buy.
std::optional<std::string> colours_not_made_today(const std::vector<report::PartCount>& parts) {
  const auto& current = voxel::Palette::current_codes();
  std::map<int, int> count;
  for (const report::PartCount& p : parts)
    if (std::find(current.begin(), current.end(), p.color) == current.end())
      count[p.color] += p.quantity;
  if (count.empty()) return std::nullopt;
  std::string listed;
  for (const auto& [code, n] : count)
    listed += fmt::format("{}{} ({}) x {}", listed.empty() ? "" : ", ",
                          ldraw::ColorTable::standard().name(code), code, n);
  return fmt::format(
      "the BrickLink wanted list holds colours LEGO does not make today in these bricks (retired, "
      "or made in other parts): {}; sellers may have them only used, or not at all; --palette "
      "current keeps to colours made today",
      listed);
}

// The outputs the options name, but the heat maps (a piece built apart adds its own).
std::vector<app::Output> named_outputs(const app::LegolizeOptions& o) {
  return {{"-o", o.output},
          {"--parts-list", o.parts_list},
          {"--bricklink", o.bricklink},
          {"--report", o.report_path}};
}

// The memory budgets' measures. A grid cell is a byte and a colour (13 bytes), rounded up. A voxel
// kept: the crate sample at --height 100 (218,376 voxels kept, 45,671 bricks) peaked at 2.4 GB in
// its build order, 11 kB a voxel, rounded up.
constexpr double kBytesPerGridCell = 16, kBytesPerVoxelKept = 12 << 10;

Plan check_options(const app::LegolizeOptions& o) {
  const std::string ext = ascii_lower(fs::path(o.output).extension().string());
  if (ext != ".ldr" && ext != ".mpd")
    throw InputError(o.output, 0, "-o: the model is written as .ldr or .mpd");
  std::vector<app::Output> outputs = named_outputs(o);
  outputs.push_back({"--heatmap", o.heatmap});
  app::check_outputs(outputs, {o.input});
  if (!o.instructions.empty()) report::check_booklet_folder(o.instructions);
  if (const std::string why = memory_shortfall(double(o.max_voxels) * kBytesPerGridCell,
                                               fmt::format("a grid of {} voxels", o.max_voxels));
      !why.empty())
    throw InputError("", 0, "--max-voxels: " + why);
  if (o.voxels_only && !o.heatmap.empty())
    throw InputError("", 0, "--heatmap needs the brick layout; --voxels-only stops before it");
  Plan p;
  p.mesh.default_color = voxel::from_hex(solid_colour("--default-color", o.default_color));
  // Uncoloured surfaces match the default exactly: it is in the palette.
  p.palette = parse_palette(o.palette_spec).with(o.default_color, ldraw::ColorTable::standard());
  solid_colour("--support-color", o.support_color);
  if (!o.bricklink.empty())
    check_bricklink_colours(p.palette, o.no_supports ? -1 : o.support_color);
  if (o.up != "auto") p.mesh.up = mesh::parse_up_axis(o.up);
  p.mesh.guard_seconds = o.read_seconds;
  const BrickCatalog& catalog = BrickCatalog::standard();
  p.rules.color = o.colors == "soft" ? layout::ColorRule::Soft : layout::ColorRule::Hard;
  p.rules.w_c = o.w_c;
  p.rules.limits.inside_color = kInsideColor;
  if (!o.inventory.empty()) p.rules.limits.read_inventory(o.inventory, catalog);
  for (const auto& l : o.limits) p.rules.limits.add(l, catalog);
  p.refine.min_cm_gf = o.min_cm;
  p.refine.fail_max = o.fail_max;
  p.refine.max_seconds =
      o.max_seconds > 0 ? std::min(o.refine_seconds, o.max_seconds / 3) : o.refine_seconds;
  p.refine.side_by_side = o.jobs > 1;
  if (o.no_local_bounds) p.refine.bound_ring = -1;
  p.refine.inside_color = kInsideColor;
  p.refine.support_color = p.rules.limits.support_color = o.support_color;
  p.refine.stability.ground =
      o.ground == "table" ? physics::GroundMode::Table : physics::GroundMode::Baseplate;
  p.refine.loads.top_grams = o.load_top;
  for (const auto& l : o.loads) p.refine.loads.at_voxels.push_back(parse_load(l));
  p.voxelize = {.height_bricks = o.height,
                .fit = {0, 0, 0},
                .mm_per_unit = o.scale,
                .max_voxels = o.max_voxels};
  if (!o.size.empty()) p.voxelize.fit = parse_size(o.size);
  return p;
}

// Mesh to voxels (paper section 3): read, voxelized, hollowed, coloured from the palette.
struct Voxels {
  voxel::VoxelGrid grid;
  layout::Target target;
};

Voxels read_and_voxelize(Run& run, const Plan& p) {
  const app::LegolizeOptions& o = run.o;
  auto t = Clock::now();
  run.stage("reading " + o.input);
  const mesh::Mesh m = mesh::load_mesh(o.input, p.mesh);
  // The files the mesh brought with it (material libraries, textures, buffers) are inputs too.
  std::vector<app::Output> outputs = named_outputs(o);
  outputs.push_back({"--heatmap", o.heatmap});
  app::check_outputs(outputs, m.files_read);
  run.rep.up = m.up;
  for (const std::string& w : m.warnings) {
    if (o.strict) throw InputError(o.input, 0, w + " (--strict)");
    std::cerr << "legolize: warning: " << w << "\n";
    run.rep.warnings.push_back(w);
  }
  run.rep.seconds.emplace_back("mesh", seconds_since(t));
  t = Clock::now();
  voxel::VoxelGrid grid = voxel::voxelize(m, p.voxelize);
  if (!o.solid) voxel::hollow(grid, o.shell);
  run.rep.inside_voxels_coloured = voxel::colour_seen_inside(grid);
  layout::Target target = layout::target_from_voxels(grid, p.palette);
  run.rep.voxels = {grid.width, grid.height, grid.depth};
  run.rep.voxels_filled = target.filled();
  run.rep.seconds.emplace_back("voxelize", seconds_since(t));
  run.stage(fmt::format("{} x {} x {} voxels, {} kept; up is {}", grid.width, grid.height,
                        grid.depth, run.rep.voxels_filled, m.up));
  if (run.rep.voxels_filled == 0) throw InputError(o.input, 0, "the mesh leaves no voxel to build");
  if (const std::string why =
          memory_shortfall(double(run.rep.voxels_filled) * kBytesPerVoxelKept,
                           fmt::format("a model of {} voxels", run.rep.voxels_filled));
      !why.empty())
    throw OutOfMemory("out of memory: " + why + " (a smaller --height needs less)");
  for (const auto& l : p.refine.loads.at_voxels)
    if (target.at(l.x, l.y, l.z) == layout::kEmpty)
      throw InputError("", 0,
                       fmt::format("--load {},{},{}: no voxel there (the grid is {} x {} x {})",
                                   l.x, l.y, l.z, grid.width, grid.height, grid.depth));
  return {std::move(grid), std::move(target)};
}

using Files = std::vector<std::pair<fs::path, std::string>>;

// The files, all or none: every text is made before any file is written, so a refused BrickLink
// list (an unmapped color) or an unwritable heat map leaves nothing behind. Then the booklet, of
// the file as written. `heat_maps` adds theirs to the files.
void write_outputs(Run& run, const std::vector<const Assembly*>& assemblies,
                   const std::string& title, const std::function<void(Files&)>& heat_maps) {
  const app::LegolizeOptions& o = run.o;
  report::ConversionReport& rep = run.rep;
  const auto t = Clock::now();
  ldraw::WriteOptions w;
  w.title = title;
  w.author = "legolize";
  Assembly all;  // every piece's bricks, for the parts lists
  for (const Assembly* a : assemblies) {
    all.bricks.insert(all.bricks.end(), a->bricks.begin(), a->bricks.end());
    for (const Brick& b : a->bricks) ++rep.bricks_by_part[b.type->part];
  }
  rep.bricks = all.bricks.size();
  const auto parts = report::count_parts(all);
  Files files;
  files.emplace_back(o.output, ldraw::model_text(o.output, assemblies, w));
  if (!o.parts_list.empty()) files.emplace_back(o.parts_list, report::parts_list_csv(parts));
  if (!o.bricklink.empty()) {
    files.emplace_back(o.bricklink, report::bricklink_xml(parts, report::BrickLinkMap::standard()));
    if (auto words = colours_not_made_today(parts)) {
      std::cerr << "legolize: warning: " << *words << "\n";
      rep.warnings.push_back(*words);
    }
  }
  if (heat_maps) heat_maps(files);
  rep.seconds.emplace_back("output", seconds_since(t));
  rep.seconds.emplace_back("total", seconds_since(run.start));
  if (!o.report_path.empty()) files.emplace_back(o.report_path, report_json(rep));
  ldraw::write_files_atomically(files);
  run.written = true;
  if (o.instructions.empty()) return;
  const ldraw::Model written = ldraw::read_file(o.output);
  report::Booklet booklet = report::booklet_of(written);
  for (report::BookletStep& bs : booklet.steps)
    if (bs.number >= 1 && bs.number <= int(rep.steps.size())) {
      const auto& st = rep.steps[size_t(bs.number - 1)];
      if (st.supports)
        bs.note =
            "Supports, not the model's: build these columns first, on the baseplate. The model "
            "stands on them; take them away only if it is held otherwise.";
      if (!st.analysed) continue;
      if (std::isfinite(st.cm_gf)) bs.cm_gf = st.cm_gf;
      bs.stands = st.stands;
      bs.certified = st.certified;
      bs.floats = st.floating > 0;
      bs.why = st.why;
      // The parts it names, found in the file written by where they are.
      for (size_t i = 0; i < written.parts.size(); ++i)
        for (const auto& at : st.falling_at)
          if (written.parts[i].step <= bs.number &&
              std::abs(written.parts[i].transform.pos[0] - at[0]) < 0.5 &&
              std::abs(written.parts[i].transform.pos[1] - at[1]) < 0.5 &&
              std::abs(written.parts[i].transform.pos[2] - at[2]) < 0.5)
            bs.falling.push_back(i);
    }
  report::draw_what_falls(booklet, written);
  if (std::isfinite(rep.cm_gf_final)) booklet.cm_gf = rep.cm_gf_final;
  booklet.verdict = fmt::format("The finished model: C_M = {} ({}).", cm_words(rep.cm_gf_final),
                                rep.stable ? "it stands" : "it does not stand");
  if (!rep.bottleneck.empty()) booklet.verdict += " Weakest: " + rep.bottleneck + ".";
  if (!rep.bottleneck_bricks.empty() || !rep.steps_stand)
    booklet.verdict += std::string(" ") + layout::kWhereOnModelKey;
  const std::string note =
      report::write_booklet(o.instructions, booklet, default_parts_dir(), run.stage_sink());
  if (!note.empty()) std::cerr << "legolize: " << note << "\n";
}

void print_bricks(const Run& run, const voxel::VoxelGrid& grid) {
  const BrickCatalog& catalog = BrickCatalog::standard();
  std::string by_part;
  for (const auto& [part, n] : run.rep.bricks_by_part)
    by_part +=
        fmt::format("{}{} {}", by_part.empty() ? "" : ", ", n,
                    catalog.find(part) ? readable_part_name(catalog.find(part)->name) : part);
  std::cout << fmt::format("{}: {} bricks ({}), {} x {} x {} voxels\n", run.o.output,
                           run.rep.bricks, by_part, grid.width, grid.height, grid.depth);
}

// --voxels-only: the voxels as 1x1 bricks, written and counted.
int write_voxels(Run& run, const Plan& p, const Voxels& v) {
  const layout::LayoutAssembly la = layout::to_assembly(
      layout::Layout(v.target), BrickCatalog::standard(), kInsideColor, p.refine.loads);
  run.rep.status_initial = run.rep.status_final = "not analysed (--voxels-only)";
  run.rep.cm_gf_initial = run.rep.cm_gf_final = std::numeric_limits<double>::quiet_NaN();  // null
  run.rep.stable = run.rep.steps_stand = true;
  write_outputs(run, {&la.assembly}, "Voxels of " + fs::path(run.o.input).stem().string(), {});
  print_bricks(run, v.grid);
  return 0;
}

// A piece built apart gets a heat map of its own: its file is checked with the others, before
// the work, as the files the user named were.
std::vector<fs::path> heat_map_paths(const app::LegolizeOptions& o, size_t pieces) {
  std::vector<fs::path> paths;
  if (o.heatmap.empty()) return paths;
  std::vector<app::Output> outputs = named_outputs(o);
  for (size_t k = 0; k < pieces; ++k) {
    paths.push_back(k == 0 ? fs::path(o.heatmap) : piece_file(o.heatmap, int(k) + 1));
    outputs.push_back({"--heatmap", paths.back().string()});
  }
  app::check_outputs(outputs, {o.input});
  return paths;
}

// What the mesh leaves in the air stands on columns (layout/pieces.h), said and reported.
void stand_floating_objects(Run& run, layout::Target& target) {
  const layout::FloatingSupports f = layout::stand_floating_objects(target);
  run.rep.floating = {f.objects, f.columns, f.voxels, f.still_floating};
  if (f.objects > 0)
    run.stage(fmt::format("{} object{} in the air: {} support column{} ({} voxels) under {}{}",
                          f.objects, f.objects == 1 ? "" : "s", f.columns,
                          f.columns == 1 ? "" : "s", f.voxels, f.objects == 1 ? "it" : "them",
                          f.still_floating ? fmt::format(", {} resting on each other still in "
                                                         "the air",
                                                         f.still_floating)
                                           : std::string()));
}

// Every piece from its voxels to an assembly whose build steps stand (convert_piece), the
// scene's separate objects apart (layout/pieces.h).
std::vector<PieceResult> convert_pieces(const Run& run, Plan& p,
                                        std::vector<layout::Piece>& pieces) {
  const app::LegolizeOptions& o = run.o;
  if (pieces.size() > 1)
    run.stage(fmt::format("{} pieces: {} object{} on the ground, {} not reaching it", pieces.size(),
                          pieces.front().grounded() ? pieces.front().objects : 0,
                          pieces.front().grounded() && pieces.front().objects == 1 ? "" : "s",
                          pieces.size() - (pieces.front().grounded() ? 1 : 0)));
  Random rng(o.seed);
  PieceSettings settings;
  settings.catalog = &BrickCatalog::standard();
  settings.rules = &p.rules;
  settings.trades = layout::ColorTrades::within(p.palette.codes(), o.color_trade);
  settings.refine = p.refine;
  settings.refine_layout = !o.no_refine;
  settings.add_supports = !o.no_supports;
  settings.supports.stability = p.refine.stability;
  settings.supports.inside_color = p.refine.inside_color;
  settings.supports.support_color = p.refine.support_color;
  settings.supports.limits = &p.rules.limits;
  settings.supports.min_cm_gf = o.min_cm;
  settings.supports.side_by_side = o.jobs > 1;
  settings.min_cm = o.min_cm;
  settings.stage = run.stage_sink();
  settings.connect.fail_max = o.fail_max;
  // Pieces standing on the ground are not floating: the stability analysis judges them.
  settings.connect.ground_connects = settings.refine.ground_connects = true;
  auto last = Clock::now();
  settings.connect.progress = [&](int iteration, int components, int fails) {
    if (o.quiet || seconds_since(last) < 0.5) return;
    last = Clock::now();
    run.stage(fmt::format("initialize: iteration {}, {} components, fail count {}", iteration,
                          components, fails));
  };
  settings.refine.progress = [&](const layout::RefineProgress& pr) {
    if (o.quiet || seconds_since(last) < 0.5) return;
    last = Clock::now();
    run.stage(fmt::format("refine: iteration {}, C_M {}, fail count {}, {} accepted", pr.iteration,
                          cm_words(pr.cm_gf), pr.fail_count, pr.accepted));
  };
  settings.supports.progress = [&](int columns, double cm_gf) {
    if (o.quiet) return;
    last = Clock::now();
    run.stage(fmt::format("columns: {} (inside the hollow or supports), C_M {}", columns,
                          cm_words(cm_gf)));
  };
  settings.order.stability = p.refine.stability;
  settings.order.min_cm_gf = o.min_cm;
  settings.order.analyse = !o.no_step_analysis;
  settings.order.max_new_bricks = o.max_step_parts;
  settings.order.side_by_side = o.jobs > 1;
  std::vector<PieceResult> results;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const layout::Piece& piece = pieces[k];
    if (pieces.size() > 1)
      run.stage(fmt::format("piece {} of {}: {} voxels{}", k + 1, pieces.size(), piece.voxels,
                            piece.grounded()
                                ? ", on the ground"
                                : fmt::format(", {} layers up, built apart", piece.lift)));
    // The loads on this piece, in its own layers; --load-top weighs on the first piece.
    settings.refine.loads = {};
    if (k == 0) settings.refine.loads.top_grams = p.refine.loads.top_grams;
    for (layout::VoxelLoad l : p.refine.loads.at_voxels)
      if (l.y >= piece.lift && piece.target.at(l.x, l.y - piece.lift, l.z) != layout::kEmpty) {
        l.y -= piece.lift;
        settings.refine.loads.at_voxels.push_back(l);
      }
    settings.supports.loads = settings.refine.loads;
    settings.order.progress = [&](int step, int placed, double seconds) {
      if (o.quiet || seconds_since(last) < 0.5) return;
      last = Clock::now();
      run.stage(
          fmt::format("build order: step {}, {} bricks placed ({:.1f} s)", step, placed, seconds));
    };
    results.push_back(convert_piece(pieces[k], rng, settings));
  }
  return results;
}

// A piece's build steps in the report, numbered after those of the pieces before it; a step
// that falls with where its falling bricks are in the written model.
void add_steps(const PieceResult& r, report::ConversionReport& rep) {
  for (size_t st = 0; st < r.order.steps.size(); ++st) {
    const layout::BuildStep& bs = r.order.steps[st];
    rep.steps.push_back({int(rep.steps.size()) + 1,
                         bs.new_bricks,
                         bs.bricks,
                         bs.status == physics::StabilityStatus::Solved
                             ? bs.cm_gf
                             : -std::numeric_limits<double>::infinity(),
                         bs.analysed,
                         bs.stands,
                         bs.why,
                         bs.certified,
                         int(st) < r.order.supports_steps,
                         bs.floating,
                         {}});
    const Assembly& placed = r.la.assembly;
    for (int b : bs.falling)
      rep.steps.back().falling_at.push_back(
          ldraw::brick_transform(placed.bricks[size_t(b)], placed.origin_ldu).pos);
  }
}

// The report: the model's numbers are its pieces' together, its C_M the weakest piece's, whose
// index is returned.
size_t report_pieces(Run& run, const std::vector<PieceResult>& results) {
  report::ConversionReport& rep = run.rep;
  rep.stable = rep.steps_stand = rep.single_connected = rep.decided = true;
  rep.support_color = run.o.support_color;
  rep.steps_analysed = !run.o.no_step_analysis;
  size_t weakest = 0;
  double seconds_initialize = 0, seconds_refine = 0, seconds_supports = 0, seconds_order = 0;
  for (size_t k = 0; k < results.size(); ++k) {
    const PieceResult& r = results[k];
    const double cm = layout::comparable_cm_gf(r.refined.final);
    if (cm < layout::comparable_cm_gf(results[weakest].refined.final)) weakest = k;
    rep.components += r.connect.components;
    rep.pieces_before_joining += r.pieces_before;
    rep.voxels_added_to_join += r.voxels_added;
    rep.support_columns += r.supports.support_columns();
    rep.inside_columns += r.supports.inside_columns();
    rep.inside_column_voxels += r.supports.inside_voxels;
    rep.support_bricks += r.support_bricks;
    rep.colour_changes.visible += r.colours.visible;
    rep.colour_changes.changed += r.colours.changed;
    rep.colour_changes.mean_distance += r.colours.mean_distance * double(r.colours.changed);
    rep.colour_changes.max_distance =
        std::max(rep.colour_changes.max_distance, r.colours.max_distance);
    rep.single_connected = rep.single_connected && r.connect.single;
    rep.decided = rep.decided && physics::decided(r.refined.final.status);
    rep.stable = rep.stable && r.stable;
    rep.steps_stand = rep.steps_stand && r.steps_stand;
    rep.iterations += r.refined.iterations;
    rep.accepted += r.refined.accepted;
    rep.lp_solves += r.refined.lp_solves;
    rep.refine_out_of_time = rep.refine_out_of_time || r.refined.out_of_time;
    rep.rejected_by_bound += r.refined.rejected_by_bound;
    rep.held_back += r.order.held_back;
    seconds_initialize += r.seconds_initialize;
    seconds_refine += r.seconds_refine;
    seconds_supports += r.seconds_supports;
    seconds_order += r.seconds_order;
    if (!r.stable && rep.bottleneck.empty()) {
      rep.bottleneck =
          results.size() > 1 ? fmt::format("piece {}: {}", k + 1, r.bottleneck) : r.bottleneck;
      rep.bottleneck_bricks = r.bottleneck_bricks;
    }
    add_steps(r, rep);
    // A piece built apart (only with --no-supports: layout/pieces.h) floats where the mesh puts
    // it, whatever it is alone: brickcheck says so of the file, and so do we.
    if (!r.grounded()) {
      rep.stable = false;
      if (rep.bottleneck.empty())
        rep.bottleneck = fmt::format(
            "piece {} floats {} layers up, where the mesh puts it: nothing holds it there "
            "(--no-supports: no columns under it)",
            k + 1, r.lift);
    }
    rep.pieces.push_back(
        {.piece = int(k) + 1,
         .grounded = r.grounded(),
         .lift = r.lift,
         .objects = r.objects,
         .voxels = r.voxels,
         .bricks = r.la.assembly.bricks.size(),
         .components = r.connect.components,
         .components_before_joining = r.pieces_before,
         .voxels_added = r.voxels_added,
         .support_columns = r.supports.support_columns(),
         .support_bricks = r.support_bricks,
         .support_voxels = r.supports.voxels,
         .inside_columns = r.supports.inside_columns(),
         .inside_column_voxels = r.supports.inside_voxels,
         .cm_gf = cm,
         .stable = r.stable,
         .steps_stand = r.steps_stand,
         .submodel = k == 0 || !ldraw::is_mpd(run.o.output)
                         ? std::string()
                         : ldraw::piece_submodel_name(fs::path(run.o.output).filename().string(),
                                                      int(k) + 1)});
  }
  if (rep.colour_changes.changed > 0)
    rep.colour_changes.mean_distance /= double(rep.colour_changes.changed);
  const PieceResult& weak = results[weakest];
  rep.solver_final = weak.refined.final.stats.solver;
  rep.solver_note_final = weak.refined.final.message;
  rep.cm_gf_initial = layout::comparable_cm_gf(weak.refined.initial);
  rep.cm_gf_final = layout::comparable_cm_gf(weak.refined.final);
  rep.status_initial = physics::to_string(weak.refined.initial.status);
  rep.status_final = physics::to_string(weak.refined.final.status);
  rep.seconds.emplace_back("initialize", seconds_initialize);
  rep.seconds.emplace_back("refine", seconds_refine);
  rep.seconds.emplace_back("supports", seconds_supports);
  rep.seconds.emplace_back("build_order", seconds_order);
  return weakest;
}

// Each piece's heat map (as brickcheck's), added to the files written.
void add_heat_maps(const Run& run, const Plan& p, const std::vector<PieceResult>& results,
                   const std::vector<fs::path>& paths, const std::string& title, Files& files) {
  if (run.o.heatmap.empty()) return;
  run.stage("per-brick capacity for the heat map");
  physics::StabilityOptions with_capacity = p.refine.stability;
  with_capacity.brick_capacity = true;
  for (size_t k = 0; k < results.size(); ++k) {
    const PieceResult& r = results[k];
    const auto s = physics::analyze_stability(r.la.assembly, with_capacity);
    files.emplace_back(
        paths[k], report::render_heatmap(
                      r.la.assembly, s,
                      "Stability heat map of " + title +
                          (results.size() > 1 ? fmt::format(", piece {}", k + 1) : std::string()),
                      "legolize", [&](int brick) { return describe_brick(r, brick); }));
  }
}

void print_summary(const Run& run, const std::vector<PieceResult>& results, size_t weakest) {
  const report::ConversionReport& rep = run.rep;
  const PieceResult& weak = results[weakest];
  if (results.size() > 1)
    for (const auto& p : rep.pieces)
      std::cout << fmt::format(
          "piece {}: {} bricks, {}, C_M {}{}\n", p.piece, p.bricks,
          p.grounded
              ? fmt::format("on the ground ({} object{})", p.objects, p.objects == 1 ? "" : "s")
              : fmt::format("does not reach the ground ({} layers up): built apart{}", p.lift,
                            p.submodel.empty() ? "" : " as " + p.submodel),
          cm_words(p.cm_gf), p.stable ? "" : ", UNSTABLE");
  if (rep.voxels_added_to_join > 0)
    std::cout << fmt::format("{} voxels added to join thin parts ({} parts before, {} after)\n",
                             rep.voxels_added_to_join, rep.pieces_before_joining, rep.components);
  std::cout << fmt::format(
      "C_M {} -> {} ({}), {} iterations, {} accepted{}, {:.2f} s\n",
      analysis_words(weak.refined.initial), analysis_words(weak.refined.final),
      rep.stable    ? "stable"
      : rep.decided ? "UNSTABLE"
                    : "UNDECIDED",
      rep.iterations, rep.accepted,
      rep.refine_out_of_time
          ? fmt::format(" (the refinement stopped at its time limit, --refine-seconds {:g})",
                        run.o.refine_seconds)
          : std::string(),
      seconds_since(run.start));
  if (!rep.solver_note_final.empty())
    std::cout << fmt::format("solver: {} ({})\n", rep.solver_final, rep.solver_note_final);
  if (const auto& c = rep.colour_changes; c.changed > 0)
    std::cout << fmt::format(
        "colours: {} of {} visible voxels ({:.1f}%) built in a nearby colour (CIEDE2000 mean "
        "{:.1f}, at most {:.1f}){}\n",
        c.changed, c.visible, 100.0 * double(c.changed) / double(std::max<size_t>(c.visible, 1)),
        c.mean_distance, c.max_distance,
        run.o.colors == "soft" ? " (--colors soft)" : ", where that holds the model together");
  if (rep.support_bricks > 0) {
    const int columns = rep.support_columns + rep.floating.columns;
    std::vector<std::string> under;
    if (rep.floating.columns > 0)
      under.push_back(fmt::format("{} under {} object{} the mesh leaves in the air",
                                  rep.floating.columns, rep.floating.objects,
                                  rep.floating.objects == 1 ? "" : "s"));
    if (rep.support_columns > 0)
      under.push_back(fmt::format("{} under what hangs", rep.support_columns));
    int first = 0;  // built in the supports' own step
    for (const auto& st : rep.steps) first += st.supports ? st.new_bricks : 0;
    const std::string where =
        ldraw::is_mpd(run.o.output)
            ? "the submodel " + fs::path(run.o.output).stem().string() + "-supports.ldr"
            : std::string("the group 'Supports'");
    std::cout << fmt::format(
        "supports: {} column{} of {} bricks in {} ({}), {}, so that it stands{}; {}\n", columns,
        columns == 1 ? "" : "s", rep.support_bricks,
        ldraw::ColorTable::standard().name(rep.support_color), rep.support_color,
        fmt::join(under, " and "), rep.stable ? "" : " (it still does not)",
        size_t(first) == rep.support_bricks ? "built first, as " + where
        : first == 0                        ? std::string("each built with the layer it stands on")
                     : fmt::format("{} bricks on the ground built first, as {}; those on the "
                                   "model with the layer they stand on",
                                   first, where));
  }
  if (rep.inside_columns > 0)
    std::cout << fmt::format(
        "inside: {} column{} of {} voxels built in the model's hollow, under what its weight "
        "breaks, in the inside colour (hidden){}\n",
        rep.inside_columns, rep.inside_columns == 1 ? "" : "s", rep.inside_column_voxels,
        rep.stable ? ", so that it stands" : "");
  if (!rep.stable) std::cout << "weakest: " << rep.bottleneck << "\n";
  if (!rep.steps.empty() && !rep.steps_analysed) {
    std::cout << fmt::format("build steps: {}, not analysed (--no-step-analysis)\n",
                             rep.steps.size());
  } else if (!rep.steps.empty()) {
    const report::StepReport* smallest = &rep.steps.front();
    for (const auto& st : rep.steps)
      if (st.cm_gf < smallest->cm_gf) smallest = &st;
    std::cout << fmt::format("build steps: {}, {}; smallest step C_M {}{}\n", rep.steps.size(),
                             rep.steps_stand ? "every one stands" : "NOT every one stands",
                             smallest->certified ? "at least " : "", cm_words(smallest->cm_gf));
    for (const auto& st : rep.steps)
      if (!st.stands) std::cout << fmt::format("  step {} falls: {}\n", st.step, st.why);
  }
}

// As brickcheck ranks them: a piece that falls before a piece the solver could not decide.
int exit_code(const report::ConversionReport& rep, const std::vector<PieceResult>& results) {
  if (rep.stable && rep.steps_stand) return 0;
  bool falls = !rep.steps_stand;
  for (const PieceResult& r : results)
    falls = falls || (physics::decided(r.refined.final.status) && !r.stable);
  return falls || rep.decided ? kExitUnstable : kExitUndecided;
}

}  // namespace

// The pipeline (paper Algorithm 1): read and voxelize, lay out each piece, refine it and order
// its build, write the files.
int main(int argc, char** argv) {
  stop::install("legolize");  // before any thread starts: they inherit its signal mask
  CLI::App app{"legolize: turn a colored 3D mesh into a LEGO model that stands"};
  app::LegolizeOptions o;
  app::add_options(app, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }
  Run run(o);
  std::optional<stop::Deadline> deadline;  // ended before `run` is
  if (o.max_seconds > 0)
    deadline.emplace(o.max_seconds, [&run, &o] {
      return stop::Ending{fmt::format("out of time ({:g} s); {}", o.max_seconds, run.where()),
                          kExitUndecided};
    });
  try {
    Plan plan = check_options(o);
    Voxels voxels = read_and_voxelize(run, plan);
    if (o.voxels_only) return write_voxels(run, plan, voxels);
    if (!o.no_supports) stand_floating_objects(run, voxels.target);
    std::vector<layout::Piece> pieces = layout::split_pieces(voxels.target);
    const std::vector<fs::path> heat_maps = heat_map_paths(o, pieces.size());
    const std::vector<PieceResult> results = convert_pieces(run, plan, pieces);
    const size_t weakest = report_pieces(run, results);
    std::vector<const Assembly*> assemblies;
    for (const PieceResult& r : results) assemblies.push_back(&r.la.assembly);
    const std::string title = "LEGO " + fs::path(o.input).stem().string();
    write_outputs(run, assemblies, title, [&](Files& files) {
      add_heat_maps(run, plan, results, heat_maps, title, files);
    });
    print_bricks(run, voxels.grid);
    print_summary(run, results, weakest);
    return exit_code(run.rep, results);
  } catch (const InputError& e) {
    std::cerr << "legolize: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const OutOfMemory& e) {
    std::cerr << "legolize: " << e.what() << "; " << run.where() << "\n";
    return kExitUndecided;
  } catch (const std::bad_alloc&) {
    std::cerr << "legolize: out of memory: an allocation failed; " << run.where() << "\n";
    return kExitUndecided;
  }
}
