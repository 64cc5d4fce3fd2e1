#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "core/text.h"
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
    case Verdict::NotJudged:
      return "NOT JUDGED";
    case Verdict::StableByAssumption:
      return "STABLE ONLY BY ASSUMPTION";
    case Verdict::Unreadable:
      return "UNREADABLE";
  }
  return "?";
}

std::string plural(size_t n, const char* word) {
  return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

std::string verdict_reason(const Audit& a) {
  using physics::StabilityStatus;
  const auto& r = a.stability;
  switch (a.verdict) {
    case Verdict::Unreadable:
      return a.fatal;
    case Verdict::NothingToAnalyse:
      return "no part could be analysed as structure";
    default:
      break;
  }
  if (!a.out_of_time.empty()) return a.out_of_time + " (--max-seconds)";
  if (!a.out_of_memory.empty()) return a.out_of_memory;
  std::string why;
  if (a.verdict == Verdict::NotJudged)
    return fmt::format(
        "{} of {} parts carried, {:.0f}% of the mass: what is analysed says too little (C_M of "
        "it {:.3f} gf)",
        a.assumptions.carried, a.assumptions.parts, 100 * a.assumptions.carried_share(), r.cm_gf());
  switch (r.status) {
    case StabilityStatus::Floating:
      why = "nothing stands on the ground";
      break;
    case StabilityStatus::NoEquilibrium:
      why = "no equilibrium: no set of forces holds it up";
      break;
    case StabilityStatus::Solved:
      why = fmt::format("C_M = {:.3f} gf ({:.4f} N)", r.cm_gf(), r.cm_newton());
      break;
    case StabilityStatus::Empty:
      why = "nothing but the ground is analysed";
      break;
    default:
      why = fmt::format("the solver gave up: {}", r.message);
      break;
  }
  if (const std::string assumed = a.assumptions.summary(); !assumed.empty())
    why += ", assuming " + assumed;
  const size_t floating = r.connectivity.floating.size() + r.connectivity.floating_carried.size();
  if (floating) why += fmt::format("; {} floating", plural(floating, "part"));
  if (a.first_failing_step) why += fmt::format("; step {} does not stand", *a.first_failing_step);
  if (a.unchecked_from_step)
    why +=
        fmt::format("; steps from {} on not checked within --max-seconds", *a.unchecked_from_step);
  if (a.verdict == Verdict::StableByAssumption)
    why += fmt::format(" (--strict: {} can change the verdict; the first: {})",
                       plural(a.assumptions.deciding.size(), "assumption"),
                       a.assumptions.deciding.front().text);
  return why;
}

// The report's lines, each ended by a newline.
struct Lines {
  std::string out;
  void operator()(const std::string& s) { out += s + "\n"; }
};

// What the verdict rests on that can change it (all of it under --strict).
void assumptions_section(const Audit& a, Lines& line) {
  if (a.assumptions.deciding.empty() && !a.assumptions.joints_checked) return;
  line(fmt::format("  assumptions that can change the verdict ({}):",
                   a.assumptions.deciding.size()));
  const auto& deciding = a.assumptions.deciding;
  for (size_t i = 0; i < deciding.size() && i < 20; ++i) line("    " + deciding[i].text);
  if (deciding.size() > 20) line(fmt::format("    and {} more", deciding.size() - 20));
  if (a.assumptions.joints_checked && a.assumptions.deciding.empty())
    line(fmt::format("    none: the {} rigid joints are not needed ({})",
                     a.assumptions.rigid_joints, a.assumptions.without_joints));
}

// What became of each placed part (analysed, carried, left out), what reading said, the loads.
void parts_section(const Audit& a, Lines& line) {
  const auto& assembly = a.conversion.assembly;
  for (const auto& d : a.model.diagnostics) line("  " + d.text());
  for (const auto& d : a.conversion.diagnostics) line("  " + d.text());
  const auto& parts = a.model.parts;
  const int turned = turned_lattice_bricks(assembly);
  line(fmt::format("  parts: {} placed: {} analysed as structure{}, {} carried, {} left out",
                   parts.size(), assembly.bricks.size(),
                   turned ? fmt::format(" ({} on turned lattices)", turned) : "",
                   assembly.carried.size(), a.conversion.skipped.size()));
  size_t estimated = 0;
  for (const auto& t : a.conversion.types->types())
    estimated += t.mass_source.starts_with("estimated");
  if (!a.conversion.types->types().empty())
    line(fmt::format("  part kinds analysed: {}, {} with a mass estimated from the body",
                     a.conversion.types->types().size(), estimated));
  if (!assembly.carried.empty()) {
    line("  carried (weight counted, connections assumed):");
    for (size_t i = 0; i < assembly.carried.size(); ++i)
      line(fmt::format("    {}: {}", describe_carried(a, int(i)),
                       carried_because(assembly.carried[i].role)));
  }
  for (const auto& s : a.conversion.skipped) {
    const auto& p = parts[s.part];
    line(fmt::format("  left out {}:{} {}: {}", p.file, p.line, p.reference, s.reason));
  }
  for (const auto& note : a.load_notes) line("  load: " + note);
}

// The joints the analysis takes as rigid: through carried parts, and where parts touch with
// nothing modelled between them (the first 20 of each kind).
void assumed_joints_section(const Audit& a, Lines& line) {
  const auto& r = a.stability;
  for (const auto& group : r.graph.carried_groups) {
    if (!group.assumed_joint()) continue;
    std::string by;
    for (int c : group.carried) by += (by.empty() ? "" : ", ") + describe_carried(a, c);
    line("  assumed rigid joint through " + by + ":");
    for (int b : group.joins) line("    " + describe_brick(a, b));
  }
  auto touching = [&](const std::vector<int>& joints, const std::string& where) {
    if (joints.empty()) return;
    line(fmt::format("  assumed rigid {} where {}:", plural(joints.size(), "joint"), where));
    for (size_t i = 0; i < joints.size() && i < 20; ++i) {
      const auto& c = r.graph.contacts[size_t(joints[i])];
      line("    " + describe_brick(a, c.lower) + " and " + describe_brick(a, c.upper));
    }
    if (joints.size() > 20) line(fmt::format("    and {} more", joints.size() - 20));
  };
  touching(r.graph.lattice_joints,
           "parts of two lattices touch (parts placed at an angle, analysed in their own frame)");
  touching(r.graph.pivot_joints, "hinge or turntable halves touch without a line they share");
}

// What reaches the ground, and when no forces hold the model: whether it tips over, which joints
// turn, which parts nothing holds; parts drawn twice in one place.
void connectivity_section(const Audit& a, Lines& line) {
  const auto& assembly = a.conversion.assembly;
  const auto& r = a.stability;
  const auto& c = r.connectivity;
  int grounded = 0;
  for (char g : c.grounded) grounded += g;
  int fixed = 0;
  for (char f : r.graph.fixed) fixed += f;
  line(fmt::format(
      "  connectivity: {}, {} on the ground{}",
      plural(size_t(c.component_count), "snapped component"), grounded,
      fixed ? fmt::format(" ({} the ground)", plural(size_t(fixed), "baseplate or fixed part is"))
            : ""));
  for (int b : c.floating) line("    floating " + describe_brick(a, b));
  const bool tips = r.status == physics::StabilityStatus::NoEquilibrium && r.graph.tips_over;
  if (tips) {
    // What it stands on, rather than the parts a least virtual force would hold: on a model that
    // tips, that force goes wherever its lever is longest (a dish at the far end).
    std::vector<int> standing;
    for (const auto& c : r.graph.contacts)
      if (c.lower == physics::kGround &&
          std::find(standing.begin(), standing.end(), c.upper) == standing.end())
        standing.push_back(c.upper);
    line(fmt::format(
        "  it tips over: its centre of mass is over nothing it stands on, however it settles; it "
        "stands on {}:",
        plural(standing.size(), "part")));
    for (size_t i = 0; i < standing.size() && i < 10; ++i)
      line("    " + describe_brick(a, standing[i]));
    if (standing.size() > 10) line(fmt::format("    and {} more", standing.size() - 10));
  }
  if (!r.turning.empty()) {
    line(fmt::format(
        "  no equilibrium: {} turn{} and must not (the least moment each would have to hold "
        "about its axis):",
        plural(r.turning.size(), "joint"), r.turning.size() == 1 ? "s" : ""));
    for (size_t i = 0; i < r.turning.size() && i < 20; ++i) {
      const auto& c = r.graph.contacts[size_t(r.turning[i].first)];
      line(fmt::format("    {} and {}: {:.3f} gf·stud", describe_brick(a, c.lower),
                       describe_brick(a, c.upper), r.turning[i].second / physics::kGravity));
    }
  }
  if (!r.unbalanced.empty() && !tips && r.turning.empty()) {
    line(fmt::format("  no equilibrium: nothing holds {} (they tip or hang):",
                     plural(r.unbalanced.size(), "part")));
    for (size_t i = 0; i < r.unbalanced.size() && i < 20; ++i)
      line("    " + describe_brick(a, r.unbalanced[i]));
    if (r.unbalanced.size() > 20) line(fmt::format("    and {} more", r.unbalanced.size() - 20));
  }
  for (int k : c.floating_carried) line("    floating (carried) " + describe_carried(a, k));
  // Bodies that share volume are common (a pin in a hole, a part drawn inside another); the same
  // part twice in one place is a mistake.
  for (auto [x, y] : r.graph.overlaps) {
    const Brick &bx = assembly.bricks[size_t(x)], &by = assembly.bricks[size_t(y)];
    const Pose px = model_pose(bx), py = model_pose(by);
    if (bx.type->part == by.type->part && px.origin == py.origin && px.rotation == py.rotation)
      line(fmt::format("    duplicated parts: {} and {}", describe_brick(a, x),
                       describe_brick(a, y)));
  }
}

// C_M and the contacts that limit it.
void stability_section(const Audit& a, Lines& line) {
  const auto& r = a.stability;
  if (r.status != physics::StabilityStatus::Solved) return;
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
  if (!r.message.empty()) line("  solver: " + r.stats.solver + " (" + r.message + ")");
}

// The independent structures solved apart (a town's buildings), the weakest five.
void structures_section(const Audit& a, Lines& line) {
  const auto& r = a.stability;
  if (r.blocks.size() <= 1) return;
  const size_t shown = std::min<size_t>(r.blocks.size(), 5);
  line(fmt::format("  structures solved apart: {}; the weakest {}:", r.blocks.size(), shown));
  for (size_t i = 0; i < shown; ++i) {
    const physics::BlockOutcome& b = r.blocks[i];
    const std::string state = b.status == physics::StabilityStatus::Solved
                                  ? fmt::format("{:.3f} gf", b.cm_gf())
                                  : std::string(physics::to_string(b.status));
    const std::string what =
        b.structures > 1 ? fmt::format("{} small structures", b.structures) : "one structure";
    std::string first = "-";
    if (!b.bricks.empty()) {
      first = describe_brick(a, b.bricks.front());
      const std::string& submodel = placed_part(a, b.bricks.front()).submodel;
      if (!submodel.empty()) first += " in " + one_line(submodel);
    }
    line(fmt::format("    {:>16}  {}, {}, the first {}", state, what,
                     plural(b.bricks.size(), "part"), first));
  }
}

// Each build step's C_M or certificate, and why a step does not stand.
void steps_section(const Audit& a, Lines& line) {
  if (a.steps.empty()) return;
  line("  build steps:");
  for (const auto& s : a.steps) {
    std::string state = s.status != physics::StabilityStatus::Solved
                            ? std::string(physics::to_string(s.status))
                        : s.certified ? fmt::format("stands (certified C_M >= {:.3f} gf)", s.cm_gf)
                                      : fmt::format("C_M = {:9.3f} gf", s.cm_gf);
    if (s.floating) state += fmt::format(", {} floating", plural(size_t(s.floating), "part"));
    if (s.apart)
      state += fmt::format(", {} of a sub-assembly built apart (judged alone on the table)",
                           plural(size_t(s.aside), "part"));
    else if (s.built_aside)
      state += fmt::format(
          ", {} built aside (a sub-assembly, set in place later; judged alone on the table)",
          plural(size_t(s.aside), "part"));
    else if (s.aside)
      state += fmt::format(", {} built aside (a sub-assembly, set in place later)",
                           plural(size_t(s.aside), "part"));
    line(fmt::format("    step {:3}: {:5} bricks  {}{}", s.step, s.bricks, state,
                     s.stable ? "" : "  <- does not stand: " + s.why));
  }
}

void time_section(const Audit& a, Lines& line) {
  const auto& r = a.stability;
  line(fmt::format(
      "  time: parse {:.3f} s, parts {:.3f} s, graph {:.3f} s, build LP {:.3f} s, "
      "solve {:.3f} s ({} rows, {} columns){}",
      a.parse_seconds, a.parts_seconds, r.stats.graph_seconds, r.stats.build_seconds,
      r.stats.solve_seconds, r.stats.rows, r.stats.columns,
      a.analyses > 1 ? fmt::format("; {} analyses, each before the last naming parts carried "
                                   "since (resting where they cannot stay, or on a tilted "
                                   "lattice that nothing holds)",
                                   a.analyses)
                     : ""));
}

}  // namespace

std::string render_text(const Audit& a, bool quiet) {
  Lines line;
  line(fmt::format("{}: {}: {}", one_line(a.file), verdict_word(a), verdict_reason(a)));
  if (quiet || a.verdict == Verdict::Unreadable || !a.out_of_time.empty() ||
      !a.out_of_memory.empty())
    return line.out;
  assumptions_section(a, line);
  parts_section(a, line);
  if (a.verdict == Verdict::NothingToAnalyse) return line.out;
  assumed_joints_section(a, line);
  connectivity_section(a, line);
  stability_section(a, line);
  structures_section(a, line);
  steps_section(a, line);
  time_section(a, line);
  return line.out;
}

}  // namespace lego::report
