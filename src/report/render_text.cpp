#include <fmt/format.h>

#include "report/render.h"

namespace lego::report {
namespace {

const char* verdict_word(const Audit& a) {
  switch (a.verdict) {
    case Verdict::Stable:
      return "STABLE";
    case Verdict::Unstable:
      return "UNSTABLE";
    case Verdict::Undecided:
      return "UNDECIDED";
    case Verdict::NothingToAnalyse:
      return "NOTHING TO ANALYSE";
    case Verdict::Unreadable:
      return "UNREADABLE";
  }
  return "?";
}

std::string verdict_reason(const Audit& a) {
  using physics::StabilityStatus;
  const auto& r = a.stability;
  switch (a.verdict) {
    case Verdict::Unreadable:
      return a.fatal;
    case Verdict::NothingToAnalyse:
      return "no part could be analysed as a brick";
    default:
      break;
  }
  std::string why;
  switch (r.status) {
    case StabilityStatus::Floating:
      why = fmt::format("{} floating brick{}", r.connectivity.floating.size(),
                        r.connectivity.floating.size() == 1 ? "" : "s");
      if (!a.conversion.skipped.empty())
        why +=
            fmt::format(" (they may rest on the {} part{} left out)", a.conversion.skipped.size(),
                        a.conversion.skipped.size() == 1 ? "" : "s");
      break;
    case StabilityStatus::NoEquilibrium:
      why = "no equilibrium: no set of forces holds it up";
      break;
    case StabilityStatus::Solved:
      why = fmt::format("C_M = {:.3f} gf ({:.4f} N)", r.cm_gf(), r.cm_newton());
      break;
    default:
      why = fmt::format("the solver gave up: {}", r.message);
      break;
  }
  if (a.first_failing_step) why += fmt::format("; step {} does not stand", *a.first_failing_step);
  return why;
}

}  // namespace

std::string render_text(const Audit& a, bool quiet) {
  std::string out;
  auto line = [&](const std::string& s) { out += s + "\n"; };
  std::string scope = a.conversion.skipped.empty() || a.verdict == Verdict::Unreadable
                          ? ""
                          : " (the verdict covers only the analysed bricks)";
  line(fmt::format("{}: {}: {}{}", a.file, verdict_word(a), verdict_reason(a), scope));
  if (quiet || a.verdict == Verdict::Unreadable) return out;

  for (const auto& d : a.model.diagnostics) line("  " + d.text());
  const auto& parts = a.model.parts;
  line(fmt::format("  parts: {} placed, {} analysed as bricks, {} left out", parts.size(),
                   a.conversion.assembly.bricks.size(), a.conversion.skipped.size()));
  for (const auto& t : a.conversion.learnt->types())
    line(
        fmt::format("    analysed from its part file: {} {} ({} x {} studs, {} plates high, {}; "
                    "mass {:.2f} g {})",
                    t.part, t.name, t.length, t.width, t.height, t.kind, t.mass_g, t.mass_source));
  for (const auto& s : a.conversion.skipped) {
    const auto& p = parts[s.part];
    line(fmt::format("    left out {}:{} {}: {}", p.file, p.line, p.reference, s.reason));
  }
  for (const auto& note : a.load_notes) line("  load: " + note);
  if (a.verdict == Verdict::NothingToAnalyse) return out;

  const auto& r = a.stability;
  const auto& c = r.connectivity;
  int grounded = 0;
  for (char g : c.grounded) grounded += g;
  line(fmt::format("  connectivity: {} snapped component{}, {} on the ground", c.component_count,
                   c.component_count == 1 ? "" : "s", grounded));
  for (int b : c.floating) line("    floating " + describe_brick(a, b));
  for (auto [x, y] : r.graph.overlaps)
    line(fmt::format("    overlapping bricks: {} and {}", describe_brick(a, x),
                     describe_brick(a, y)));
  if (r.status == physics::StabilityStatus::Solved) {
    line(fmt::format(
        "  stability: C_M = {:.3f} gf = {:.4f} N (maximum friction load T = 71.658 gf per point)",
        r.cm_gf(), r.cm_newton()));
    size_t shown = std::min<size_t>(r.weakest.size(), 5);
    if (shown) line("  weakest contacts (share of the binding duals):");
    for (size_t i = 0; i < shown; ++i) {
      const auto& w = r.weakest[i];
      line(fmt::format("    {:5.1f}%  {} holding {}", 100 * w.share, describe_brick(a, w.lower),
                       describe_brick(a, w.upper)));
    }
    if (!shown) line("  no contact needs friction: the model stands on its normal forces alone");
  }
  if (!a.steps.empty()) {
    line("  build steps:");
    for (const auto& s : a.steps)
      line(fmt::format(
          "    step {:3}: {:5} bricks  {}", s.step, s.bricks,
          s.status == physics::StabilityStatus::Solved
              ? fmt::format("C_M = {:9.3f} gf{}", s.cm_gf, s.stable ? "" : "  <- does not stand")
              : fmt::format("{}  <- does not stand", physics::to_string(s.status))));
  }
  line(
      fmt::format("  time: parse {:.3f} s, graph {:.3f} s, build LP {:.3f} s, solve {:.3f} s ({} "
                  "rows, {} columns)",
                  a.parse_seconds, r.stats.graph_seconds, r.stats.build_seconds,
                  r.stats.solve_seconds, r.stats.rows, r.stats.columns));
  return out;
}

}  // namespace lego::report
