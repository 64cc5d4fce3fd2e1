// legolize: a colored mesh to a LEGO model that stands (paper Algorithm 1): voxels with LEGO
// proportions, a maximal single-connected brick layout, stability-aware refinement, and LDraw
// files whose build steps each stand (layout/build_order.h), with instructions on request.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include "app/number_checks.h"
#include "app/output_paths.h"
#include "core/brick_catalog.h"
#include "core/error.h"
#include "core/lattice.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "layout/build_order.h"
#include "layout/pieces.h"
#include "layout/reconfigure.h"
#include "layout/refine.h"
#include "layout/to_assembly.h"
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
std::string describe_brick(const PieceResult& piece, int brick);

// How every piece is converted: the options the user gave, shared by all pieces.
struct PieceSettings {
  const BrickCatalog* catalog = nullptr;
  layout::MergeRules* rules = nullptr;  // its limits are used up piece by piece
  layout::RefineOptions refine;
  layout::ConnectOptions connect;
  layout::BuildOrderOptions order;
  bool refine_layout = true;
  double min_cm = 0;
  std::function<void(const std::string&)> stage;
};

// One piece of the model (layout/pieces.h), from its voxels to an assembly whose build steps
// stand: layout initialization with thin parts joined (Algorithm 3), stability-aware refinement
// (Algorithm 7) and the build order.
struct PieceResult {
  int lift = 0, objects = 0;
  size_t voxels = 0;
  std::optional<layout::Layout> lay;
  layout::LayoutAssembly la;
  layout::ConnectResult connect;
  int pieces_before = 0;
  size_t voxels_added = 0;
  layout::RefineResult refined;  // `final` is the finished piece's analysis
  bool stable = true, steps_stand = true;
  std::string bottleneck;
  layout::BuildOrder order;
  double seconds_initialize = 0, seconds_refine = 0, seconds_order = 0;
};

PieceResult convert_piece(layout::Piece& piece, Random& rng, const PieceSettings& s) {
  PieceResult out;
  out.lift = piece.lift;
  out.objects = piece.objects;
  out.voxels = piece.voxels;
  auto t = Clock::now();
  layout::JoinedLayout joined =
      layout::initialize_joined(std::move(piece.target), *s.rules, rng, s.connect);
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
  t = Clock::now();
  const bool refining = out.connect.single && s.refine_layout;
  if (refining) {
    s.stage("refining");
    out.refined = layout::refine_layout(lay, *s.catalog, *s.rules, rng, s.refine);
    out.stable = out.refined.stable;
    s.stage(fmt::format(
        "refined: C_M {} -> {}, {} iterations, {} accepted; {} whole-model analyses, {} "
        "candidates rejected on local bounds ({:.2f} s)",
        analysis_words(out.refined.initial), analysis_words(out.refined.final),
        out.refined.iterations, out.refined.accepted, out.refined.lp_solves,
        out.refined.rejected_by_bound, out.refined.bound_seconds));
  }
  out.seconds_refine = seconds_since(t);
  out.la = layout::to_assembly(lay, *s.catalog, s.refine.inside_color, s.refine.loads);
  if (!refining) {
    out.refined.initial = out.refined.final =
        physics::analyze_stability(out.la.assembly, s.refine.stability);
    out.stable = out.stable && out.refined.final.stable(s.min_cm);
  }
  if (!out.stable && out.bottleneck.empty()) {
    const auto& f = out.refined.final;
    out.bottleneck = f.weakest.empty()
                         ? std::string(physics::to_string(f.status))
                         : describe_brick(out, f.weakest.front().lower) + " holding " +
                               describe_brick(out, f.weakest.front().upper);
  }
  // What this piece uses is not there for the next (after the refinement, which may change it).
  s.rules->limits.use_up(lay);
  // A building order in which every step stands (the paper's first limitation).
  t = Clock::now();
  layout::BuildOrderOptions order = s.order;
  order.describe = [&out](int brick) { return describe_brick(out, brick); };
  out.order = layout::plan_build_order(out.la.assembly, order);
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
  // Where the piece was lowered from: its bricks go back there in the model.
  out.la.assembly.origin_ldu[1] -= out.lift * kPlatesPerBrick * kLduPerPlate;
  return out;
}

std::string describe_brick(const PieceResult& p, int brick) {
  if (brick == physics::kGround) return "the ground";
  const Brick& b = p.la.assembly.bricks[size_t(brick)];
  const layout::LayoutBrick& lb = p.lay->brick(p.la.layout_id[size_t(brick)]);
  return fmt::format("{} {} at voxel {},{},{}", b.type->part, b.type->name, lb.x, lb.y + p.lift,
                     lb.z);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"legolize: turn a colored 3D mesh into a LEGO model that stands"};
  std::string input, output, up = "auto", palette_spec = "current", size, colors = "hard",
                             ground = "baseplate", inventory, parts_list, bricklink, report_path,
                             heatmap, instructions;
  int height = 20, shell = 3, fail_max = 100, default_color = kUncolouredColor,
      max_step_parts = layout::BuildOrderOptions{}.max_new_bricks;
  size_t max_voxels = 8'000'000;
  double scale = 0, w_c = 1, min_cm = 0, load_top = 0, read_seconds = 120;
  uint64_t seed = 1;
  bool voxels_only = false, solid = false, no_refine = false, quiet = false,
       no_step_analysis = false;
  std::vector<std::string> limits, loads;
  app.add_option(
         "mesh", input,
         "any mesh format Assimp reads (OBJ+MTL, STL, PLY, glTF/GLB, FBX, 3MF, OFF, DAE...)")
      ->required();
  app.add_option("-o,--output", output, "the LDraw model to write (.ldr or .mpd)")->required();

  auto* g_size = "Size and voxels";
  app.add_option("--height", height, "model height in bricks (default 20)")
      ->check(CLI::Range(1, 10000))
      ->group(g_size);
  app.add_option("--size", size, "fit within W studs x H bricks x D studs, as WxHxD")
      ->group(g_size);
  app.add_option("--scale", scale, "millimetres per mesh unit (overrides --height and --size)")
      ->check(app::finite_number(app::Sign::Positive))
      ->group(g_size);
  app.add_option("--up", up,
                 "the mesh's up axis in the file's own coordinates: x, -x, y, -y, z, -z, or auto "
                 "(default: what the file or its format declares, else y)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return text == "auto" || mesh::parse_up_axis(text)
                       ? std::string()
                       : "'" + text + "' is not auto, x, -x, y, -y, z or -z";
          },
          "AXIS"))
      ->group(g_size);
  app.add_option("--shell", shell, "keep voxels within N voxels of the surface (default 3)")
      ->check(CLI::Range(1, 1000))
      ->group(g_size);
  app.add_flag("--solid", solid, "do not hollow")->group(g_size);
  app.add_option("--palette", palette_spec,
                 "current (default: 39 colours LEGO makes today, each on BrickLink), paper (the "
                 "paper's eight), all (every solid LDraw colour), or LDraw codes: 15,4,1")
      ->group(g_size);
  app.add_option("--default-color", default_color,
                 "LDraw colour for surfaces the mesh gives no colour (default 71, Light Bluish "
                 "Grey); it joins the palette")
      ->group(g_size);
  app.add_option("--read-seconds", read_seconds,
                 "the mesh is read first in a child process: give up after this long (default "
                 "120); a reader that crashes or hangs on the file is then an error, not a crash")
      ->check(app::finite_number(app::Sign::Positive))
      ->group(g_size);
  app.add_option("--max-voxels", max_voxels, "refuse grids larger than this (default 8,000,000)")
      ->check(app::finite_number(app::Sign::Positive))
      ->group(g_size);
  app.add_flag("--voxels-only", voxels_only, "write the voxels as 1x1 bricks and stop")
      ->group(g_size);

  auto* g_layout = "Layout";
  app.add_option("--seed", seed, "the random seed: same input and seed, same output (default 1)")
      ->group(g_layout);
  app.add_option("--colors", colors,
                 "hard: no brick spans two colors (default); soft: allow some, see --wc")
      ->check(CLI::IsMember({"hard", "soft"}))
      ->group(g_layout);
  app.add_option("--wc", w_c, "soft colors: larger keeps colors truer (paper's w_c, default 1)")
      ->check(app::finite_number(app::Sign::NonNegative))
      ->group(g_layout);
  app.add_option("--limit", limits,
                 "at most N bricks of a size or part, optionally in a color: 2x4:100, 2x8:0, "
                 "3001@14:50 (repeatable)")
      ->group(g_layout);
  app.add_option("--inventory", inventory,
                 "CSV part,color,quantity of the bricks you have; nothing else is used")
      ->group(g_layout);
  app.add_option("--fail-max", fail_max, "failed reconfigurations in a row before giving up (100)")
      ->check(CLI::Range(1, 1000000))
      ->group(g_layout);

  auto* g_physics = "Stability";
  app.add_option("--min-cm", min_cm, "refine until C_M exceeds this many grams-force (default 0)")
      ->check(app::finite_number())
      ->group(g_physics);
  app.add_option("--load-top", load_top, "a weight in grams spread over the model's top knobs")
      ->check(app::finite_number(app::Sign::NonNegative, physics::kMaxLoadGrams))
      ->group(g_physics);
  app.add_option("--load", loads,
                 "X,Y,Z:GRAMS, a weight on the brick at voxel X,Y,Z (Y = layer; repeatable)")
      ->group(g_physics);
  app.add_option("--ground", ground, "baseplate: the ground holds knobs (default); table: pushes")
      ->check(CLI::IsMember({"baseplate", "table"}))
      ->group(g_physics);
  app.add_flag("--no-refine", no_refine, "skip the stability-aware refinement")->group(g_physics);
  app.add_flag("--no-step-analysis", no_step_analysis,
               "order the build steps by studs alone, without analysing each step (each analysis "
               "costs about half the final one; the report then says so)")
      ->group(g_physics);
  app.add_option("--max-step-parts", max_step_parts,
                 fmt::format("new parts in one build step at most: a layer with more is built in "
                             "groups of nearby parts (default {}; 0: a layer per step)",
                             max_step_parts))
      ->check(CLI::NonNegativeNumber)
      ->group(g_physics);
  bool no_local_bounds = false;
  app.add_flag("--no-local-bounds", no_local_bounds,
               "analyse every refinement candidate on the whole model instead of rejecting "
               "most on a local upper bound first (the same result, slower; for comparison)")
      ->group(g_physics);
  int jobs = 2;
  app.add_option("--jobs", jobs,
                 "analyses run at once, one thread each (default 2): the refinement's two "
                 "candidates per round; the output does not depend on it")
      ->check(CLI::Range(1, 64))
      ->group(g_physics);

  auto* g_out = "Outputs";
  app.add_option("--parts-list", parts_list, "CSV: part, LDraw color, name, quantity")
      ->group(g_out);
  app.add_option("--bricklink", bricklink, "BrickLink XML wanted list")->group(g_out);
  app.add_option("--report", report_path, "JSON report (docs/legolize-report.md)")->group(g_out);
  app.add_option("--heatmap", heatmap, "LDraw model colored by stability (as brickcheck's)")
      ->group(g_out);
  app.add_option("--instructions", instructions,
                 "write an HTML booklet into this folder: a page per build step with a picture "
                 "(LeoCAD), its parts and its C_M")
      ->group(g_out);
  app.add_flag("--quiet", quiet, "no progress on stderr")->group(g_out);
  bool strict = false;
  app.add_flag("--strict", strict,
               "what the mesh names but cannot be used (a texture not found or unreadable) is an "
               "error (exit 2) instead of a warning")
      ->group(g_out);
  app.footer(
      "Exit codes: 0 written, stable, and every build step stands; 1 written, but unstable, not "
      "one connected piece, or a build step falls (the report and summary say where); 2 usage "
      "error or bad input (nothing is written); 4 written, but the stability solver gave up "
      "(UNDECIDED, as brickcheck says).");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }

  const auto start = Clock::now();
  auto stage = [&](const std::string& words) {
    if (!quiet) std::cerr << fmt::format("legolize [{:7.2f} s] {}\n", seconds_since(start), words);
  };
  report::ConversionReport rep;
  rep.input = input;
  rep.output = output;
  rep.seed = seed;
  rep.version = LEGOLIZATION_VERSION;
  rep.min_cm_gf = min_cm;
  try {
    // Everything the user typed is checked before the work starts.
    const std::string ext = ascii_lower(fs::path(output).extension().string());
    if (ext != ".ldr" && ext != ".mpd")
      throw InputError(output, 0, "-o: the model is written as .ldr or .mpd");
    app::check_outputs({{"-o", output},
                        {"--parts-list", parts_list},
                        {"--bricklink", bricklink},
                        {"--report", report_path},
                        {"--heatmap", heatmap}},
                       {input});
    if (!instructions.empty()) report::check_booklet_folder(instructions);
    if (voxels_only && !heatmap.empty())
      throw InputError("", 0, "--heatmap needs the brick layout; --voxels-only stops before it");
    mesh::MeshOptions mesh_options;
    const auto default_rgb = ldraw::ColorTable::standard().rgb(default_color);
    if (!default_rgb || default_color == ldraw::kMainColor || default_color == ldraw::kEdgeColor)
      throw InputError(
          "", 0, fmt::format("--default-color: {} is not in the colour table", default_color));
    mesh_options.default_color = voxel::from_hex(*default_rgb);
    // Uncoloured surfaces match the default exactly: it is in the palette.
    const voxel::Palette palette =
        parse_palette(palette_spec).with(default_color, ldraw::ColorTable::standard());
    if (up != "auto") mesh_options.up = mesh::parse_up_axis(up);
    mesh_options.guard_seconds = read_seconds;
    const BrickCatalog& catalog = BrickCatalog::standard();
    layout::MergeRules rules;
    rules.color = colors == "soft" ? layout::ColorRule::Soft : layout::ColorRule::Hard;
    rules.w_c = w_c;
    rules.limits.inside_color = kInsideColor;
    if (!inventory.empty()) rules.limits.read_inventory(inventory, catalog);
    for (const auto& l : limits) rules.limits.add(l, catalog);
    layout::RefineOptions refine;
    refine.min_cm_gf = min_cm;
    refine.fail_max = fail_max;
    refine.side_by_side = jobs > 1;
    if (no_local_bounds) refine.bound_ring = -1;
    refine.inside_color = kInsideColor;
    refine.stability.ground =
        ground == "table" ? physics::GroundMode::Table : physics::GroundMode::Baseplate;
    refine.loads.top_grams = load_top;
    for (const auto& l : loads) refine.loads.at_voxels.push_back(parse_load(l));
    voxel::VoxelizeOptions vo{
        .height_bricks = height, .fit = {0, 0, 0}, .mm_per_unit = scale, .max_voxels = max_voxels};
    if (!size.empty()) vo.fit = parse_size(size);

    // Mesh to voxels (paper section 3).
    auto t = Clock::now();
    stage("reading " + input);
    const mesh::Mesh m = mesh::load_mesh(input, mesh_options);
    rep.up = m.up;
    for (const std::string& w : m.warnings) {
      if (strict) throw InputError(input, 0, w + " (--strict)");
      std::cerr << "legolize: warning: " << w << "\n";
      rep.warnings.push_back(w);
    }
    rep.seconds.emplace_back("mesh", seconds_since(t));
    t = Clock::now();
    voxel::VoxelGrid grid = voxel::voxelize(m, vo);
    if (!solid) voxel::hollow(grid, shell);
    rep.inside_voxels_coloured = voxel::colour_seen_inside(grid);
    const layout::Target target = layout::target_from_voxels(grid, palette);
    rep.voxels = {grid.width, grid.height, grid.depth};
    rep.voxels_filled = target.filled();
    rep.seconds.emplace_back("voxelize", seconds_since(t));
    stage(fmt::format("{} x {} x {} voxels, {} kept; up is {}", grid.width, grid.height, grid.depth,
                      rep.voxels_filled, m.up));
    if (rep.voxels_filled == 0) throw InputError(input, 0, "the mesh leaves no voxel to build");
    for (const auto& l : refine.loads.at_voxels)
      if (target.at(l.x, l.y, l.z) == layout::kEmpty)
        throw InputError("", 0,
                         fmt::format("--load {},{},{}: no voxel there (the grid is {} x {} x {})",
                                     l.x, l.y, l.z, grid.width, grid.height, grid.depth));

    // The files, all or none: every text is made before any file is written, so a refused
    // BrickLink list (an unmapped color) or an unwritable heat map leaves nothing behind. Then the
    // booklet, of the file as written. `heat_maps` adds theirs to the files.
    using Files = std::vector<std::pair<fs::path, std::string>>;
    auto write_outputs = [&](const std::vector<const Assembly*>& assemblies,
                             const std::string& title,
                             const std::function<void(Files&)>& heat_maps) {
      t = Clock::now();
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
      files.emplace_back(output, ldraw::model_text(output, assemblies, w));
      if (!parts_list.empty()) files.emplace_back(parts_list, report::parts_list_csv(parts));
      if (!bricklink.empty())
        files.emplace_back(bricklink,
                           report::bricklink_xml(parts, report::BrickLinkMap::standard()));
      if (heat_maps) heat_maps(files);
      rep.seconds.emplace_back("output", seconds_since(t));
      rep.seconds.emplace_back("total", seconds_since(start));
      if (!report_path.empty()) files.emplace_back(report_path, report_json(rep));
      ldraw::write_files_atomically(files);
      if (instructions.empty()) return;
      report::Booklet booklet = report::booklet_of(ldraw::read_file(output));
      for (report::BookletStep& bs : booklet.steps)
        if (bs.number >= 1 && bs.number <= int(rep.steps.size())) {
          const auto& st = rep.steps[size_t(bs.number - 1)];
          if (!st.analysed) continue;
          if (std::isfinite(st.cm_gf)) bs.cm_gf = st.cm_gf;
          bs.stands = st.stands;
          bs.certified = st.certified;
          bs.why = st.why;
        }
      if (std::isfinite(rep.cm_gf_final)) booklet.cm_gf = rep.cm_gf_final;
      booklet.verdict = fmt::format("The finished model: C_M = {} ({}).", cm_words(rep.cm_gf_final),
                                    rep.stable ? "it stands" : "it does not stand");
      const std::string note =
          report::write_booklet(instructions, booklet, output, default_parts_dir(), stage);
      if (!note.empty()) std::cerr << "legolize: " << note << "\n";
    };
    auto print_bricks = [&] {
      std::string by_part;
      for (const auto& [part, n] : rep.bricks_by_part)
        by_part += fmt::format("{}{} {}", by_part.empty() ? "" : ", ", n,
                               catalog.find(part) ? catalog.find(part)->name : part);
      std::cout << fmt::format("{}: {} bricks ({}), {} x {} x {} voxels\n", output, rep.bricks,
                               by_part, grid.width, grid.height, grid.depth);
    };

    if (voxels_only) {
      const layout::LayoutAssembly la =
          layout::to_assembly(layout::Layout(target), catalog, kInsideColor, refine.loads);
      rep.status_initial = rep.status_final = "not analysed (--voxels-only)";
      rep.cm_gf_initial = rep.cm_gf_final = std::numeric_limits<double>::quiet_NaN();  // null
      rep.stable = rep.steps_stand = true;
      write_outputs({&la.assembly}, "Voxels of " + fs::path(input).stem().string(), {});
      print_bricks();
      return 0;
    }

    // A scene's separate objects (layout/pieces.h): those on the ground are one piece, every
    // other object a piece of its own, built apart.
    std::vector<layout::Piece> pieces = layout::split_pieces(target);
    // A piece built apart gets a heat map of its own: its file is checked with the others, before
    // the work, as the files the user named were.
    std::vector<fs::path> heat_map_paths;
    if (!heatmap.empty()) {
      std::vector<app::Output> outputs{{"-o", output},
                                       {"--parts-list", parts_list},
                                       {"--bricklink", bricklink},
                                       {"--report", report_path}};
      for (size_t k = 0; k < pieces.size(); ++k) {
        heat_map_paths.push_back(k == 0 ? fs::path(heatmap) : piece_file(heatmap, int(k) + 1));
        outputs.push_back({"--heatmap", heat_map_paths.back().string()});
      }
      app::check_outputs(outputs, {input});
    }
    if (pieces.size() > 1)
      stage(fmt::format("{} pieces: {} object{} on the ground, {} not reaching it", pieces.size(),
                        pieces.front().grounded() ? pieces.front().objects : 0,
                        pieces.front().grounded() && pieces.front().objects == 1 ? "" : "s",
                        pieces.size() - (pieces.front().grounded() ? 1 : 0)));
    Random rng(seed);
    PieceSettings settings;
    settings.catalog = &catalog;
    settings.rules = &rules;
    settings.refine = refine;
    settings.refine_layout = !no_refine;
    settings.min_cm = min_cm;
    settings.stage = stage;
    settings.connect.fail_max = fail_max;
    // Pieces standing on the ground are not floating: the stability analysis judges them.
    settings.connect.ground_connects = settings.refine.ground_connects = true;
    auto last = Clock::now();
    settings.connect.progress = [&](int iteration, int components, int fails) {
      if (quiet || seconds_since(last) < 0.5) return;
      last = Clock::now();
      stage(fmt::format("initialize: iteration {}, {} components, fail count {}", iteration,
                        components, fails));
    };
    settings.refine.progress = [&](const layout::RefineProgress& p) {
      if (quiet || seconds_since(last) < 0.5) return;
      last = Clock::now();
      stage(fmt::format("refine: iteration {}, C_M {}, fail count {}, {} accepted", p.iteration,
                        cm_words(p.cm_gf), p.fail_count, p.accepted));
    };
    settings.order.stability = refine.stability;
    settings.order.min_cm_gf = min_cm;
    settings.order.analyse = !no_step_analysis;
    settings.order.max_new_bricks = max_step_parts;
    settings.order.side_by_side = jobs > 1;
    std::vector<PieceResult> results;
    for (size_t k = 0; k < pieces.size(); ++k) {
      const layout::Piece& p = pieces[k];
      if (pieces.size() > 1)
        stage(fmt::format(
            "piece {} of {}: {} voxels{}", k + 1, pieces.size(), p.voxels,
            p.grounded() ? ", on the ground" : fmt::format(", {} layers up, built apart", p.lift)));
      // The loads on this piece, in its own layers; --load-top weighs on the first piece.
      settings.refine.loads = {};
      if (k == 0) settings.refine.loads.top_grams = refine.loads.top_grams;
      for (layout::VoxelLoad l : refine.loads.at_voxels)
        if (l.y >= p.lift && p.target.at(l.x, l.y - p.lift, l.z) != layout::kEmpty) {
          l.y -= p.lift;
          settings.refine.loads.at_voxels.push_back(l);
        }
      settings.order.progress = [&](int step, int placed, double seconds) {
        if (quiet || seconds_since(last) < 0.5) return;
        last = Clock::now();
        stage(fmt::format("build order: step {}, {} bricks placed ({:.1f} s)", step, placed,
                          seconds));
      };
      results.push_back(convert_piece(pieces[k], rng, settings));
    }

    // The report: the model's numbers are its pieces' together, its C_M the weakest piece's.
    t = Clock::now();
    rep.stable = rep.steps_stand = rep.single_connected = rep.decided = true;
    rep.steps_analysed = !no_step_analysis;
    size_t weakest = 0;
    double seconds_initialize = 0, seconds_refine = 0, seconds_order = 0;
    for (size_t k = 0; k < results.size(); ++k) {
      const PieceResult& r = results[k];
      const double cm = layout::comparable_cm_gf(r.refined.final);
      if (cm < layout::comparable_cm_gf(results[weakest].refined.final)) weakest = k;
      rep.components += r.connect.components;
      rep.pieces_before_joining += r.pieces_before;
      rep.voxels_added_to_join += r.voxels_added;
      rep.single_connected = rep.single_connected && r.connect.single;
      rep.decided = rep.decided && physics::decided(r.refined.final.status);
      rep.stable = rep.stable && r.stable;
      rep.steps_stand = rep.steps_stand && r.steps_stand;
      rep.iterations += r.refined.iterations;
      rep.accepted += r.refined.accepted;
      rep.lp_solves += r.refined.lp_solves;
      rep.rejected_by_bound += r.refined.rejected_by_bound;
      rep.held_back += r.order.held_back;
      seconds_initialize += r.seconds_initialize;
      seconds_refine += r.seconds_refine;
      seconds_order += r.seconds_order;
      if (!r.stable && rep.bottleneck.empty())
        rep.bottleneck =
            results.size() > 1 ? fmt::format("piece {}: {}", k + 1, r.bottleneck) : r.bottleneck;
      for (const layout::BuildStep& bs : r.order.steps)
        rep.steps.push_back({int(rep.steps.size()) + 1, bs.new_bricks, bs.bricks,
                             bs.status == physics::StabilityStatus::Solved
                                 ? bs.cm_gf
                                 : -std::numeric_limits<double>::infinity(),
                             bs.analysed, bs.stands, bs.why, bs.certified});
      rep.pieces.push_back(
          {.piece = int(k) + 1,
           .grounded = r.lift == 0,
           .lift = r.lift,
           .objects = r.objects,
           .voxels = r.voxels,
           .bricks = r.la.assembly.bricks.size(),
           .components = r.connect.components,
           .components_before_joining = r.pieces_before,
           .voxels_added = r.voxels_added,
           .cm_gf = cm,
           .stable = r.stable,
           .steps_stand = r.steps_stand,
           .submodel =
               k == 0 || !ldraw::is_mpd(output)
                   ? std::string()
                   : ldraw::piece_submodel_name(fs::path(output).filename().string(), int(k) + 1)});
    }
    const PieceResult& weak = results[weakest];
    rep.solver_final = weak.refined.final.stats.solver;
    rep.solver_note_final = weak.refined.final.message;
    rep.cm_gf_initial = layout::comparable_cm_gf(weak.refined.initial);
    rep.cm_gf_final = layout::comparable_cm_gf(weak.refined.final);
    rep.status_initial = physics::to_string(weak.refined.initial.status);
    rep.status_final = physics::to_string(weak.refined.final.status);
    rep.seconds.emplace_back("initialize", seconds_initialize);
    rep.seconds.emplace_back("refine", seconds_refine);
    rep.seconds.emplace_back("build_order", seconds_order);

    // Outputs.
    std::vector<const Assembly*> assemblies;
    for (const PieceResult& r : results) assemblies.push_back(&r.la.assembly);
    const std::string title = "LEGO " + fs::path(input).stem().string();
    write_outputs(assemblies, title, [&](Files& files) {
      if (heatmap.empty()) return;
      stage("per-brick capacity for the heat map");
      physics::StabilityOptions with_capacity = refine.stability;
      with_capacity.brick_capacity = true;
      for (size_t k = 0; k < results.size(); ++k) {
        const PieceResult& r = results[k];
        const auto s = physics::analyze_stability(r.la.assembly, with_capacity);
        files.emplace_back(
            heat_map_paths[k],
            report::render_heatmap(
                r.la.assembly, s,
                "Stability heat map of " + title +
                    (results.size() > 1 ? fmt::format(", piece {}", k + 1) : std::string()),
                "legolize", [&](int brick) { return describe_brick(r, brick); }));
      }
    });
    print_bricks();
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
    std::cout << fmt::format("C_M {} -> {} ({}), {} iterations, {} accepted, {:.2f} s\n",
                             analysis_words(weak.refined.initial),
                             analysis_words(weak.refined.final),
                             rep.stable    ? "stable"
                             : rep.decided ? "UNSTABLE"
                                           : "UNDECIDED",
                             rep.iterations, rep.accepted, seconds_since(start));
    if (!rep.solver_note_final.empty())
      std::cout << fmt::format("solver: {} ({})\n", rep.solver_final, rep.solver_note_final);
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
    if (rep.stable && rep.steps_stand) return 0;
    // As brickcheck ranks them: a piece that falls before a piece the solver could not decide.
    bool falls = !rep.steps_stand;
    for (const PieceResult& r : results)
      falls = falls || (physics::decided(r.refined.final.status) && !r.stable);
    return falls || rep.decided ? kExitUnstable : kExitUndecided;
  } catch (const InputError& e) {
    std::cerr << "legolize: " << e.what() << "\n";
    return kExitBadInput;
  }
}
