// legolize: a colored mesh to a LEGO model that stands (paper Algorithm 1): voxels with LEGO
// proportions, a maximal single-connected brick layout, stability-aware refinement, and LDraw
// files whose build steps each stand (layout/build_order.h), with instructions on request.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "app/number_checks.h"
#include "core/brick_catalog.h"
#include "core/error.h"
#include "layout/build_order.h"
#include "layout/reconfigure.h"
#include "layout/refine.h"
#include "layout/to_assembly.h"
#include "ldraw/reader.h"
#include "ldraw/writer.h"
#include "mesh/mesh.h"
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
constexpr int kExitUnstable = 1, kExitBadInput = 2;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

voxel::Palette parse_palette(const std::string& spec) {
  const auto& table = ldraw::ColorTable::standard();
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
  return load;
}

// Fails before any work when an output cannot be written or would overwrite the input.
void check_output(const std::string& option, const std::string& path, const fs::path& input) {
  if (path.empty()) return;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(path, 0, option + ": the folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw InputError(path, 0, option + ": the folder " + dir.string() + " is not writable");
  if (fs::is_directory(p, ec)) throw InputError(path, 0, option + ": is a folder");
  if (fs::exists(p, ec) && fs::equivalent(p, input, ec))
    throw InputError(path, 0, option + ": would overwrite the input mesh");
}

std::string cm_words(double cm_gf) {
  return std::isfinite(cm_gf) ? fmt::format("{:.3f} gf", cm_gf) : std::string("no equilibrium");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"legolize: turn a colored 3D mesh into a LEGO model that stands"};
  std::string input, output, up = "y", palette_spec = "paper", size, colors = "hard",
                             ground = "baseplate", inventory, parts_list, bricklink, report_path,
                             heatmap, instructions;
  int height = 20, shell = 3, fail_max = 100, default_color = -1;
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
  app.add_option("--up", up, "the mesh's up axis")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->group(g_size);
  app.add_option("--shell", shell, "keep voxels within N voxels of the surface (default 3)")
      ->check(CLI::Range(1, 1000))
      ->group(g_size);
  app.add_flag("--solid", solid, "do not hollow")->group(g_size);
  app.add_option("--palette", palette_spec,
                 "paper (the paper's eight colours), all, or LDraw codes: 15,4,1")
      ->group(g_size);
  app.add_option("--default-color", default_color,
                 "LDraw colour for surfaces the mesh gives no colour (default: grey)")
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
      ->check(app::finite_number(app::Sign::NonNegative))
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
  bool no_local_bounds = false;
  app.add_flag("--no-local-bounds", no_local_bounds,
               "analyse every refinement candidate on the whole model instead of rejecting "
               "most on a local upper bound first (the same result, slower; for comparison)")
      ->group(g_physics);
  int jobs = 2;
  app.add_option("--jobs", jobs,
                 "refinement candidates analysed at once, one thread each (default 2; 1 is the "
                 "paper's sequential loop); more than 1 also analyses two build steps at once")
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
  app.footer(
      "Exit codes: 0 written, stable, and every build step stands; 1 written, but unstable, not "
      "one connected piece, or a build step falls (the report and summary say where); 2 usage "
      "error or bad input (nothing is written).");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }

  const auto start = Clock::now();
  auto stage = [&](const std::string& words) {
    if (!quiet) std::cerr << fmt::format("legolize [{:7.2f} s] {}\n", since(start), words);
  };
  report::ConversionReport rep;
  rep.input = input;
  rep.output = output;
  rep.seed = seed;
  rep.version = LEGOLIZATION_VERSION;
  rep.min_cm_gf = min_cm;
  try {
    // Everything the user typed is checked before the work starts.
    std::string ext = fs::path(output).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".ldr" && ext != ".mpd")
      throw InputError(output, 0, "-o: the model is written as .ldr or .mpd");
    check_output("-o", output, input);
    check_output("--parts-list", parts_list, input);
    check_output("--bricklink", bricklink, input);
    check_output("--report", report_path, input);
    check_output("--heatmap", heatmap, input);
    if (!instructions.empty()) report::check_booklet_folder(instructions);
    if (voxels_only && !heatmap.empty())
      throw InputError("", 0, "--heatmap needs the brick layout; --voxels-only stops before it");
    const voxel::Palette palette = parse_palette(palette_spec);
    mesh::MeshOptions mesh_options;
    if (default_color >= 0) {
      auto rgb = ldraw::ColorTable::standard().rgb(default_color);
      if (!rgb)
        throw InputError(
            "", 0, fmt::format("--default-color: {} is not in the colour table", default_color));
      mesh_options.default_color = voxel::from_hex(*rgb);
    }
    mesh_options.up = up == "x" ? mesh::UpAxis::X : up == "z" ? mesh::UpAxis::Z : mesh::UpAxis::Y;
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
    refine.candidates_per_round = jobs;
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
    rep.seconds.emplace_back("mesh", since(t));
    t = Clock::now();
    voxel::VoxelGrid grid = voxel::voxelize(m, vo);
    if (!solid) voxel::hollow(grid, shell);
    layout::Layout lay(layout::target_from_voxels(grid, palette));
    rep.voxels = {grid.width, grid.height, grid.depth};
    rep.voxels_filled = lay.target().filled();
    rep.seconds.emplace_back("voxelize", since(t));
    stage(fmt::format("{} x {} x {} voxels, {} kept", grid.width, grid.height, grid.depth,
                      rep.voxels_filled));
    if (rep.voxels_filled == 0) throw InputError(input, 0, "the mesh leaves no voxel to build");
    for (const auto& l : refine.loads.at_voxels)
      if (lay.brick_at(l.x, l.y, l.z) < 0)
        throw InputError("", 0,
                         fmt::format("--load {},{},{}: no voxel there (the grid is {} x {} x {})",
                                     l.x, l.y, l.z, grid.width, grid.height, grid.depth));

    Random rng(seed);
    bool stable = true;
    layout::RefineResult refined;
    if (!voxels_only) {
      // Layout initialization (Algorithm 3).
      t = Clock::now();
      layout::ConnectOptions connect;
      connect.fail_max = fail_max;
      // Pieces standing on the ground are not floating: the stability analysis judges them.
      connect.ground_connects = refine.ground_connects = true;
      auto last = Clock::now();
      connect.progress = [&](int iteration, int components, int fails) {
        if (quiet || since(last) < 0.5) return;
        last = Clock::now();
        stage(fmt::format("initialize: iteration {}, {} components, fail count {}", iteration,
                          components, fails));
      };
      const layout::ConnectResult c = layout::initialize_layout(lay, rules, rng, connect);
      if (auto exceeded = rules.limits.exceeded(lay); !exceeded.empty()) {
        std::string words;
        for (const auto& e : exceeded) words += "\n  " + e;
        throw InputError("", 0,
                         "impossible limits: the model needs more bricks than allowed:" + words);
      }
      rep.components = c.components;
      rep.single_connected = c.single;
      rep.seconds.emplace_back("initialize", since(t));
      stage(fmt::format("initialized: {} bricks, {} component{} ({} at first, {} iterations)",
                        lay.brick_count(), c.components, c.components == 1 ? "" : "s",
                        c.components_start, c.iterations));
      if (!c.single) {
        stable = false;
        rep.bottleneck = fmt::format(
            "no single connected layout after {} failed tries: {} pieces that no brick joins",
            fail_max, c.components);
      }
      // Stability-aware refinement (Algorithm 7).
      t = Clock::now();
      if (c.single && !no_refine) {
        last = Clock::now();
        refine.progress = [&](const layout::RefineProgress& p) {
          if (quiet || since(last) < 0.5) return;
          last = Clock::now();
          stage(fmt::format("refine: iteration {}, C_M {}, fail count {}, {} accepted", p.iteration,
                            cm_words(p.cm_gf), p.fail_count, p.accepted));
        };
        stage("refining");
        refined = layout::refine_layout(lay, catalog, rules, rng, refine);
        rep.cm_gf_initial = layout::comparable_cm_gf(refined.initial);
        rep.cm_gf_final = layout::comparable_cm_gf(refined.final);
        rep.status_initial = physics::to_string(refined.initial.status);
        rep.status_final = physics::to_string(refined.final.status);
        rep.iterations = refined.iterations;
        rep.accepted = refined.accepted;
        rep.lp_solves = refined.lp_solves;
        rep.rejected_by_bound = refined.rejected_by_bound;
        stable = refined.stable;
        stage(fmt::format(
            "refined: C_M {} -> {}, {} iterations, {} accepted; {} whole-model analyses, {} "
            "candidates rejected on local bounds ({:.2f} s)",
            cm_words(rep.cm_gf_initial), cm_words(rep.cm_gf_final), refined.iterations,
            refined.accepted, refined.lp_solves, refined.rejected_by_bound, refined.bound_seconds));
      }
      rep.seconds.emplace_back("refine", since(t));
    }

    // Outputs.
    t = Clock::now();
    layout::LayoutAssembly la = layout::to_assembly(lay, catalog, kInsideColor, refine.loads);
    const Assembly& assembly = la.assembly;
    if (voxels_only) {
      rep.status_initial = rep.status_final = "not analysed (--voxels-only)";
      rep.cm_gf_initial = rep.cm_gf_final = std::numeric_limits<double>::quiet_NaN();  // null
    } else if (no_refine || !rep.single_connected) {
      auto s = physics::analyze_stability(assembly, refine.stability);
      refined.final = s;
      rep.cm_gf_initial = rep.cm_gf_final = layout::comparable_cm_gf(s);
      rep.status_initial = rep.status_final = physics::to_string(s.status);
      stable = stable && s.stable(min_cm);
    }
    const physics::StabilityResult& final_result = refined.final;
    auto describe = [&](int brick) {
      if (brick == physics::kGround) return std::string("the ground");
      const layout::LayoutBrick& b = lay.brick(la.layout_id[size_t(brick)]);
      return fmt::format("{} {} at voxel {},{},{}", assembly.bricks[size_t(brick)].type->part,
                         assembly.bricks[size_t(brick)].type->name, b.x, b.y, b.z);
    };
    if (!stable && rep.bottleneck.empty()) {
      rep.bottleneck = final_result.weakest.empty()
                           ? std::string(physics::to_string(final_result.status))
                           : describe(final_result.weakest.front().lower) + " holding " +
                                 describe(final_result.weakest.front().upper);
    }
    rep.stable = stable;
    rep.steps_stand = true;
    if (!voxels_only) {
      // A building order in which every step stands (the paper's first limitation).
      t = Clock::now();
      layout::BuildOrderOptions order_options;
      order_options.stability = refine.stability;
      order_options.min_cm_gf = min_cm;
      order_options.analyse = !no_step_analysis;
      order_options.side_by_side = jobs > 1;
      auto last_progress = Clock::now();
      order_options.progress = [&](int step, int placed, double seconds) {
        if (quiet || since(last_progress) < 0.5) return;
        last_progress = Clock::now();
        stage(fmt::format("build order: step {}, {} of {} bricks placed ({:.1f} s)", step, placed,
                          la.assembly.bricks.size(), seconds));
      };
      const layout::BuildOrder order = layout::plan_build_order(la.assembly, order_options);
      const std::vector<int> moved = layout::apply_build_order(la.assembly, order);
      std::vector<int> layout_id(moved.size());
      for (size_t k = 0; k < moved.size(); ++k) layout_id[k] = la.layout_id[size_t(moved[k])];
      la.layout_id = std::move(layout_id);
      for (size_t k = 0; k < order.steps.size(); ++k) {
        const layout::BuildStep& bs = order.steps[k];
        rep.steps.push_back({int(k) + 1, bs.new_bricks, bs.bricks,
                             bs.status == physics::StabilityStatus::Solved
                                 ? bs.cm_gf
                                 : -std::numeric_limits<double>::infinity(),
                             bs.analysed, bs.stands, bs.why});
      }
      rep.held_back = order.held_back;
      rep.steps_analysed = order_options.analyse;
      rep.steps_stand = !order_options.analyse || order.all_stand();
      rep.seconds.emplace_back("build_order", since(t));
      stage(order_options.analyse
                ? fmt::format("build order: {} steps, {}; smallest step C_M {}; {} analyses, "
                              "{:.2f} s",
                              order.steps.size(),
                              rep.steps_stand ? "every one stands" : "NOT every one stands",
                              cm_words(order.min_cm_gf()), order.analyses, order.seconds)
                : fmt::format("build order: {} steps, not analysed", order.steps.size()));
      t = Clock::now();
    }
    rep.bricks = assembly.bricks.size();
    rep.components = rep.components ? rep.components : final_result.connectivity.component_count;
    for (const Brick& b : assembly.bricks) ++rep.bricks_by_part[b.type->part];

    ldraw::WriteOptions w;
    w.title = (voxels_only ? "Voxels of " : "LEGO ") + fs::path(input).stem().string();
    w.author = "legolize";
    const auto parts = report::count_parts(assembly);
    // Every text is made before any file is written, and the files land all or none: a refused
    // BrickLink list (an unmapped color) or an unwritable heat map leaves nothing behind.
    std::vector<std::pair<fs::path, std::string>> files;
    files.emplace_back(output, ldraw::model_text(output, assembly, w));
    if (!parts_list.empty()) files.emplace_back(parts_list, report::parts_list_csv(parts));
    if (!bricklink.empty())
      files.emplace_back(bricklink, report::bricklink_xml(parts, report::BrickLinkMap::standard()));
    if (!heatmap.empty()) {
      stage("per-brick capacity for the heat map");
      physics::StabilityOptions with_capacity = refine.stability;
      with_capacity.brick_capacity = true;
      const auto s = physics::analyze_stability(assembly, with_capacity);
      files.emplace_back(heatmap,
                         report::render_heatmap(assembly, s, "Stability heat map of " + w.title,
                                                "legolize", describe));
    }
    rep.seconds.emplace_back("output", since(t));
    rep.seconds.emplace_back("total", since(start));
    // A file name that is not UTF-8 (a Latin-1 "café.obj") is written with U+FFFD in its place.
    if (!report_path.empty())
      files.emplace_back(
          report_path,
          to_json(rep).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    ldraw::write_files_atomically(files);
    if (!instructions.empty()) {
      // The booklet shows the file as written, read back as any LDraw tool would.
      report::Booklet booklet = report::booklet_of(ldraw::read_file(output));
      for (report::BookletStep& bs : booklet.steps)
        if (bs.number >= 1 && bs.number <= int(rep.steps.size())) {
          const auto& st = rep.steps[size_t(bs.number - 1)];
          if (!st.analysed) continue;
          if (std::isfinite(st.cm_gf)) bs.cm_gf = st.cm_gf;
          bs.stands = st.stands;
          bs.why = st.why;
        }
      if (std::isfinite(rep.cm_gf_final)) booklet.cm_gf = rep.cm_gf_final;
      booklet.verdict = fmt::format("The finished model: C_M = {} ({}).", cm_words(rep.cm_gf_final),
                                    stable ? "it stands" : "it does not stand");
      const std::string note =
          report::write_booklet(instructions, booklet, output, default_parts_dir(), stage);
      if (!note.empty()) std::cerr << "legolize: " << note << "\n";
    }

    std::string by_part;
    for (const auto& [part, n] : rep.bricks_by_part)
      by_part += fmt::format("{}{} {}", by_part.empty() ? "" : ", ", n,
                             catalog.find(part) ? catalog.find(part)->name : part);
    std::cout << fmt::format("{}: {} bricks ({}), {} x {} x {} voxels\n", output, rep.bricks,
                             by_part, grid.width, grid.height, grid.depth);
    if (!voxels_only)
      std::cout << fmt::format("C_M {} -> {} ({}), {} iterations, {} accepted, {:.2f} s\n",
                               cm_words(rep.cm_gf_initial), cm_words(rep.cm_gf_final),
                               stable ? "stable" : "UNSTABLE", rep.iterations, rep.accepted,
                               since(start));
    if (!stable) std::cout << "weakest: " << rep.bottleneck << "\n";
    if (!rep.steps.empty() && !rep.steps_analysed) {
      std::cout << fmt::format("build steps: {}, not analysed (--no-step-analysis)\n",
                               rep.steps.size());
    } else if (!rep.steps.empty()) {
      double smallest = std::numeric_limits<double>::infinity();
      for (const auto& st : rep.steps) smallest = std::min(smallest, st.cm_gf);
      std::cout << fmt::format("build steps: {}, {}; smallest step C_M {}\n", rep.steps.size(),
                               rep.steps_stand ? "every one stands" : "NOT every one stands",
                               cm_words(smallest));
      for (const auto& st : rep.steps)
        if (!st.stands) std::cout << fmt::format("  step {} falls: {}\n", st.step, st.why);
    }
    return stable && rep.steps_stand ? 0 : kExitUnstable;
  } catch (const InputError& e) {
    std::cerr << "legolize: " << e.what() << "\n";
    return kExitBadInput;
  }
}
