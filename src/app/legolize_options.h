#pragma once
// legolize's command line: every option, its default and its help, in one place.
#include <CLI/CLI.hpp>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "layout/build_order.h"
#include "layout/target.h"

namespace lego::app {

inline constexpr int kInsideColor =
    72;  // Dark Bluish Grey: voxels whose color does not matter (IGNORE)
inline constexpr int kUncolouredColor = 71;  // Light Bluish Grey: surfaces the mesh gives no colour

struct LegolizeOptions {
  std::string input, output, up = "auto", palette_spec = "current", size, colors = "hard",
                             ground = "baseplate", inventory, parts_list, bricklink, report_path,
                             heatmap, instructions;
  int height = 20, shell = 3, fail_max = 100, default_color = kUncolouredColor,
      max_step_parts = layout::BuildOrderOptions{}.max_new_bricks, jobs = 2,
      support_color = layout::kDefaultSupportColor;
  size_t max_voxels = 8'000'000;
  double scale = 0, w_c = 1, min_cm = 0, load_top = 0, read_seconds = 120, refine_seconds = 60,
         color_trade = 12, max_seconds = 0;
  uint64_t seed = 1;
  bool voxels_only = false, solid = false, no_refine = false, quiet = false,
       no_step_analysis = false, no_local_bounds = false, strict = false, no_supports = false;
  std::vector<std::string> limits, loads;
};

// Declares every option of `o` on `app`, with its checks, group and help, and the exit codes.
void add_options(CLI::App& app, LegolizeOptions& o);

}  // namespace lego::app
