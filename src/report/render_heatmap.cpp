#include <fmt/format.h>

#include "core/text.h"
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

namespace {

// The map's colour key (ending with `rest`, what else is coloured), C_M and the five weakest
// contacts, as comments.
std::string legend(const physics::StabilityResult& r, const char* rest,
                   const std::function<std::string(int)>& describe) {
  std::string out =
      "0 // Colours by the share of the friction limit T a brick's worst knob uses: red >= 100%\n"
      "0 // (overloaded), orange >= 50%, light orange >= 20%, yellow >= 5%, lime >= 0.5%,\n";
  out += rest;
  if (r.stats.capacity_solver == physics::kCapacityFromAnalysis)
    out +=
        "0 // Capacities from the analysis's own forces: the least-norm distribution was not\n"
        "0 // found, and these are one distribution that reaches C_M, not the unique one.\n";
  if (r.status == physics::StabilityStatus::Solved)
    out += fmt::format("0 // C_M = {:.3f} gf\n", r.cm_gf());
  for (size_t i = 0; i < r.weakest.size() && i < 5; ++i) {
    const auto& wk = r.weakest[i];
    out += fmt::format("0 // weakest {}: {} holding {} ({:.1f}% of the binding duals)\n", i + 1,
                       describe(wk.lower), describe(wk.upper), 100 * wk.share);
  }
  return out;
}

}  // namespace

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
  const std::string notes = legend(stability, "0 // green below; grey = not computed.\n", describe);
  // After the header (five lines and a blank), before the bricks.
  size_t at = 0;
  for (int k = 0; k < 5; ++k) at = body.find('\n', at) + 1;
  return body.insert(at, notes);
}

std::string render_heatmap(const Audit& a) {
  // Every placed part where the model puts it: analysed bricks by their capacity, the rest in
  // colours that say what they are.
  constexpr int kCarried = 71, kGroundColour = 72, kFloating = 0, kLeftOut = 15;
  const auto& r = a.stability;
  const auto& capacity = r.brick_capacity;
  std::vector<int> colour(a.model.parts.size(), kLeftOut);
  for (size_t i = 0; i < a.conversion.carried_part.size(); ++i)
    colour[a.conversion.carried_part[i]] = kCarried;
  for (size_t b = 0; b < a.conversion.brick_part.size(); ++b)
    colour[a.conversion.brick_part[b]] = b < r.graph.fixed.size() && r.graph.fixed[b]
                                             ? kGroundColour
                                         : b < capacity.size() ? heat_color(capacity[b])
                                                               : kCarried;
  for (int b : r.connectivity.floating) colour[a.conversion.brick_part[size_t(b)]] = kFloating;
  for (int c : r.connectivity.floating_carried)
    colour[a.conversion.carried_part[size_t(c)]] = kFloating;

  const std::string title =
      "Stability heat map of " + one_line(a.model.title.empty() ? a.file : a.model.title);
  std::string out = fmt::format(
      "0 {}\n0 Name: heatmap.ldr\n0 Author: brickcheck\n"
      "0 !LDRAW_ORG Unofficial_Model\n\n",
      title);
  out += legend(r,
                "0 // green below. Light grey: carried (its weight counted, its connections "
                "assumed) or\n"
                "0 // not computed; dark grey: the ground; black: floating; white: left out.\n",
                [&](int b) { return describe_brick(a, b); });
  for (const auto& group : r.graph.carried_groups) {
    if (!group.assumed_joint()) continue;
    std::string through, joins;
    for (int c : group.carried) through += (through.empty() ? "" : ", ") + describe_carried(a, c);
    for (int b : group.joins) joins += (joins.empty() ? "" : "; ") + describe_brick(a, b);
    out += fmt::format("0 // assumed rigid joint through {} joins {}\n", through, joins);
  }
  auto touching = [&](const std::vector<int>& joints, const char* where) {
    for (int k : joints) {
      const auto& c = r.graph.contacts[size_t(k)];
      out += fmt::format("0 // assumed rigid joint where {} touch joins {}; {}\n", where,
                         describe_brick(a, c.lower), describe_brick(a, c.upper));
    }
  };
  touching(r.graph.lattice_joints, "two lattices");
  touching(r.graph.pivot_joints, "hinge halves");
  auto number = [](double v) {
    std::string s = fmt::format("{:.4f}", v);
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s == "-0" ? std::string("0") : s;
  };
  for (size_t i = 0; i < a.model.parts.size(); ++i) {
    const auto& p = a.model.parts[i];
    out += fmt::format("1 {} {} {} {}", colour[i], number(p.transform.pos[0]),
                       number(p.transform.pos[1]), number(p.transform.pos[2]));
    for (double m : p.transform.rot) out += fmt::format(" {}", number(m));
    out += fmt::format(" {}\n", p.reference);
  }
  return out;
}

}  // namespace lego::report
