#include "app/legolize_options.h"

#include <fmt/format.h>

#include "app/number_checks.h"
#include "mesh/mesh.h"
#include "physics/force_model.h"

namespace lego::app {

// One list, as --help shows it: over 100 lines because there are over 30 options.
void add_options(CLI::App& app, LegolizeOptions& o) {
  app.add_option(
         "mesh", o.input,
         "any mesh format Assimp reads (OBJ+MTL, STL, PLY, glTF/GLB, FBX, 3MF, OFF, DAE...)")
      ->required();
  app.add_option("-o,--output", o.output, "the LDraw model to write (.ldr or .mpd)")->required();

  auto* g_size = "Size and voxels";
  app.add_option("--height", o.height, "model height in bricks (default 20)")
      ->check(CLI::Range(1, 10000))
      ->group(g_size);
  app.add_option("--size", o.size, "fit within W studs x H bricks x D studs, as WxHxD")
      ->group(g_size);
  app.add_option("--scale", o.scale, "millimetres per mesh unit (overrides --height and --size)")
      ->check(finite_number(Sign::Positive))
      ->group(g_size);
  app.add_option("--up", o.up,
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
  app.add_option("--shell", o.shell, "keep voxels within N voxels of the surface (default 3)")
      ->check(CLI::Range(1, 1000))
      ->group(g_size);
  app.add_flag("--solid", o.solid, "do not hollow")->group(g_size);
  app.add_option("--palette", o.palette_spec,
                 "current (default: 39 colours LEGO makes today, each on BrickLink), paper (the "
                 "paper's eight), all (every solid LDraw colour), or LDraw codes: 15,4,1")
      ->group(g_size);
  app.add_option("--default-color", o.default_color,
                 "LDraw colour for surfaces the mesh gives no colour (default 71, Light Bluish "
                 "Grey); it joins the palette")
      ->group(g_size);
  app.add_option("--read-seconds", o.read_seconds,
                 "the mesh is read first in a child process: give up after this long (default "
                 "120); a reader that crashes or hangs on the file is then an error, not a crash")
      ->check(finite_number(Sign::Positive))
      ->group(g_size);
  app.add_option("--max-voxels", o.max_voxels, "refuse grids larger than this (default 8,000,000)")
      ->check(finite_number(Sign::Positive))
      ->group(g_size);
  app.add_flag("--voxels-only", o.voxels_only, "write the voxels as 1x1 bricks and stop")
      ->group(g_size);

  auto* g_layout = "Layout";
  app.add_option("--seed", o.seed, "the random seed: same input and seed, same output (default 1)")
      ->group(g_layout);
  app.add_option("--colors", o.colors,
                 "hard: no brick spans two colors (default); soft: allow some, see --wc")
      ->check(CLI::IsMember({"hard", "soft"}))
      ->group(g_layout);
  app.add_option("--color-trade", o.color_trade,
                 "hard colors: where the layout breaks apart or does not stand, one brick may "
                 "take two colors this close (CIEDE2000; default 12, as close as Reddish Brown "
                 "and Dark Brown; 0: never); the summary says how many voxels changed")
      ->check(finite_number(Sign::NonNegative))
      ->group(g_layout);
  app.add_option("--wc", o.w_c, "soft colors: larger keeps colors truer (paper's w_c, default 1)")
      ->check(finite_number(Sign::NonNegative))
      ->group(g_layout);
  app.add_option("--limit", o.limits,
                 "at most N bricks of a size or part, optionally in a color: 2x4:100, 2x8:0, "
                 "3001@14:50 (repeatable)")
      ->group(g_layout);
  app.add_option("--inventory", o.inventory,
                 "CSV part,color,quantity of the bricks you have; nothing else is used")
      ->group(g_layout);
  app.add_option("--fail-max", o.fail_max,
                 "failed reconfigurations in a row before giving up (100)")
      ->check(CLI::Range(1, 1000000))
      ->group(g_layout);

  auto* g_physics = "Stability";
  app.add_option("--min-cm", o.min_cm, "refine until C_M exceeds this many grams-force (default 0)")
      ->check(cm_threshold(physics::kMaxFrictionLoad / physics::kGravity))
      ->group(g_physics);
  app.add_option("--load-top", o.load_top, "a weight in grams spread over the model's top knobs")
      ->check(finite_number(Sign::NonNegative, physics::kMaxLoadGrams))
      ->group(g_physics);
  app.add_option("--load", o.loads,
                 "X,Y,Z:GRAMS, a weight on the brick at voxel X,Y,Z (Y = layer; repeatable)")
      ->group(g_physics);
  app.add_option("--ground", o.ground, "baseplate: the ground holds knobs (default); table: pushes")
      ->check(CLI::IsMember({"baseplate", "table"}))
      ->group(g_physics);
  app.add_flag("--no-refine", o.no_refine, "skip the stability-aware refinement")->group(g_physics);
  app.add_option("--refine-seconds", o.refine_seconds,
                 "the refinement stops after this long (default 60); what does not stand then "
                 "gets supports")
      ->check(finite_number(Sign::Positive))
      ->group(g_physics);
  app.add_option("--max-seconds", o.max_seconds,
                 "the whole run ends after this long, whatever it is doing (reading, the layout, "
                 "the refinement, supports, build steps, the booklet): exit 4, saying where it "
                 "was; the refinement then takes at most a third of it. Default: no limit")
      ->check(finite_number(Sign::Positive))
      ->group(g_physics);
  app.add_option("--support-color", o.support_color,
                 fmt::format("LDraw colour of the supports: columns from the ground added under "
                             "what hangs when the refined layout does not stand, built first "
                             "(default {}, Medium Azure)",
                             o.support_color))
      ->group(g_physics);
  app.add_flag("--no-supports", o.no_supports,
               "never add columns, in the model's hollow or supports from the ground: a layout "
               "that does not stand is written as it is (exit 1)")
      ->group(g_physics);
  app.add_flag("--no-step-analysis", o.no_step_analysis,
               "order the build steps by studs alone, without analysing each step (each analysis "
               "costs about half the final one; the report then says so)")
      ->group(g_physics);
  app.add_option("--max-step-parts", o.max_step_parts,
                 fmt::format("new parts in one build step at most: a layer with more is built in "
                             "groups of nearby parts (default {}; 0: a layer per step)",
                             o.max_step_parts))
      ->check(CLI::NonNegativeNumber)
      ->group(g_physics);
  app.add_flag("--no-local-bounds", o.no_local_bounds,
               "analyse every refinement candidate on the whole model instead of rejecting "
               "most on a local upper bound first (the same result, slower; for comparison)")
      ->group(g_physics);
  app.add_option("--jobs", o.jobs,
                 "analyses run at once, one thread each (default 2): the refinement's two "
                 "candidates per round; the build order's next step made, and an LP solved, "
                 "ahead; the output does not depend on it")
      ->check(CLI::Range(1, 64))
      ->group(g_physics);

  auto* g_out = "Outputs";
  app.add_option("--parts-list", o.parts_list, "CSV: part, LDraw color, name, quantity")
      ->group(g_out);
  app.add_option("--bricklink", o.bricklink, "BrickLink XML wanted list")->group(g_out);
  app.add_option("--report", o.report_path, "JSON report (docs/legolize-report.md)")->group(g_out);
  app.add_option("--heatmap", o.heatmap, "LDraw model colored by stability (as brickcheck's)")
      ->group(g_out);
  app.add_option("--instructions", o.instructions,
                 "write an HTML booklet into this folder: a page per build step with a picture "
                 "(LeoCAD), its parts and its C_M")
      ->group(g_out);
  app.add_flag("--quiet", o.quiet, "no progress on stderr")->group(g_out);
  app.add_flag("--strict", o.strict,
               "what the mesh names but cannot be used (a texture not found or unreadable) is an "
               "error (exit 2) instead of a warning")
      ->group(g_out);
  app.footer(
      "Exit codes: 0 written, stable, and every build step stands; 1 written, but unstable, not "
      "one connected piece, or a build step falls (the report and summary say where); 2 usage "
      "error or bad input (nothing is written); 4 written, but the stability solver gave up "
      "(UNDECIDED, as brickcheck says).");
}

}  // namespace lego::app
