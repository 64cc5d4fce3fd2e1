#include <fmt/format.h>

#include "ldraw/writer.h"
#include "physics/force_model.h"
#include "report/render.h"

namespace lego::report {

int heat_color(double capacity) {
  // The share of the friction limit T in use, on a roughly logarithmic scale: real models load
  // their knobs to a few percent of T, and the map should still show where the load goes.
  const double used = 1 - capacity / physics::kMaxFrictionLoad;
  if (used >= 1) return 4;       // Red: overloaded
  if (used >= 0.5) return 25;    // Orange
  if (used >= 0.2) return 191;   // Bright Light Orange
  if (used >= 0.05) return 14;   // Yellow
  if (used >= 0.005) return 27;  // Lime
  return 2;                      // Green: (almost) no pull
}

std::string render_heatmap(const Assembly& assembly, const physics::StabilityResult& stability,
                           const std::string& title, const std::string& author,
                           const std::function<std::string(int)>& describe) {
  Assembly coloured = assembly;
  const auto& capacity = stability.brick_capacity;
  for (size_t i = 0; i < coloured.bricks.size(); ++i)
    coloured.bricks[i].color = i < capacity.size() ? heat_color(capacity[i]) : 71;
  ldraw::WriteOptions w;
  w.title = title;
  w.name = "heatmap.ldr";
  w.author = author;
  w.steps = false;
  std::string body = ldraw::to_ldr(coloured, w);
  std::string notes =
      "0 // Colours by the share of the friction limit T a brick's worst knob uses: red >= 100%\n"
      "0 // (overloaded), orange >= 50%, light orange >= 20%, yellow >= 5%, lime >= 0.5%,\n"
      "0 // green below; grey = not computed.\n";
  if (stability.status == physics::StabilityStatus::Solved)
    notes += fmt::format("0 // C_M = {:.3f} gf\n", stability.cm_gf());
  for (size_t i = 0; i < stability.weakest.size() && i < 5; ++i) {
    const auto& wk = stability.weakest[i];
    notes += fmt::format("0 // weakest {}: {} holding {} ({:.1f}% of the binding duals)\n", i + 1,
                         describe(wk.lower), describe(wk.upper), 100 * wk.share);
  }
  // After the header (five lines and a blank), before the bricks.
  size_t at = 0;
  for (int k = 0; k < 5; ++k) at = body.find('\n', at) + 1;
  return body.insert(at, notes);
}

std::string render_heatmap(const Audit& a) {
  return render_heatmap(a.conversion.assembly, a.stability,
                        "Stability heat map of " + (a.model.title.empty() ? a.file : a.model.title),
                        "brickcheck", [&](int brick) { return describe_brick(a, brick); });
}

}  // namespace lego::report
