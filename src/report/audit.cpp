#include "report/audit.h"

#include <fmt/format.h>
#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "core/memory.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "ldraw/writer.h"
#include "physics/force_model.h"
#include "physics/solved_blocks.h"
#include "physics/step_stability.h"
#include "physics/world_shape.h"
#include "report/drawn_by_eye.h"

namespace lego::report {
namespace {

physics::StabilityOptions with_capacity(physics::StabilityOptions o, bool capacity) {
  o.brick_capacity = capacity;
  return o;
}

// A whole decimal number, in range.
std::optional<int> whole_number(std::string_view text) {
  int v = 0;
  if (text.empty() || text.size() > 9) return std::nullopt;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || v < 0) return std::nullopt;
  return v;
}

// How many studs a load on top of the brick is shared over (at least one).
int top_studs(const Brick& b) {
  int up = 0;
  const Pose pose = pose_of(b);
  for (const Connector& s : b.type->shape.studs)
    if (lattice_direction(pose.turn(s.direction)) == kPlusY) ++up;
  return std::max(up, 1);
}

// Places each load on the bricks it names; returns a note per load, or throws InputError.
std::vector<std::string> apply_loads(Audit& audit, const std::vector<LoadSpec>& loads) {
  std::vector<std::string> notes;
  auto& assembly = audit.conversion.assembly;
  double highest = -std::numeric_limits<double>::infinity();
  std::vector<double> top(assembly.bricks.size(), highest);
  for (size_t i = 0; i < assembly.bricks.size(); ++i) {
    for (const Box& b : physics::world_shape(assembly.bricks[i]).body)
      top[i] = std::max(top[i], physics::model_bounds(assembly.bricks[i], b).max[1]);
    highest = std::max(highest, top[i]);
  }
  for (const LoadSpec& spec : loads) {
    std::vector<int> targets;
    for (int i = 0; i < int(assembly.bricks.size()); ++i) {
      const auto& part = placed_part(audit, i);
      bool hit = false;
      switch (spec.target) {
        case LoadSpec::Target::Line:
          hit = spec.line.names(part, audit.model.source);
          break;
        case LoadSpec::Target::Step:
          hit = part.step == spec.number;
          break;
        case LoadSpec::Target::Submodel:
          hit = normalize_part_name(part.submodel) == normalize_part_name(spec.name);
          break;
        case LoadSpec::Target::Top:
          hit = top[size_t(i)] >= highest - 0.5;
          break;
      }
      if (hit) targets.push_back(i);
    }
    if (targets.empty())
      throw InputError(audit.file, 0,
                       fmt::format("--load {}: names no part analysed as structure", spec.text));
    // The weight is shared by knob count, so a step's load sits evenly on all its top knobs.
    int knobs = 0;
    for (int i : targets) knobs += top_studs(assembly.bricks[size_t(i)]);
    for (int i : targets) {
      const double share = double(top_studs(assembly.bricks[size_t(i)])) / knobs;
      assembly.loads.push_back({i, {0, -weight_newton(spec.grams) * share, 0}, true, {}});
    }
    notes.push_back(fmt::format("{} g on the top knobs of {} brick{}", spec.grams, targets.size(),
                                targets.size() == 1 ? "" : "s"));
  }
  return notes;
}

Verdict verdict_of(const physics::StabilityResult& r, double min_cm_gf) {
  using physics::StabilityStatus;
  switch (r.status) {
    case StabilityStatus::Solved:
      return r.stable(min_cm_gf) ? Verdict::Stable : Verdict::Unstable;
    case StabilityStatus::Floating:
    case StabilityStatus::NoEquilibrium:
      return Verdict::Unstable;
    case StabilityStatus::IterationLimit:
    case StabilityStatus::NumericalTrouble:
      return Verdict::Undecided;
    case StabilityStatus::Empty:
      return r.connectivity.all_grounded() ? Verdict::NothingToAnalyse : Verdict::Unstable;
  }
  return Verdict::Undecided;
}

// The parts the user fixed, as indices into Model::parts.
std::vector<size_t> fixed_parts(const ldraw::Model& model, const std::vector<LineSpec>& specs,
                                const std::string& file) {
  std::vector<size_t> out;
  for (const LineSpec& spec : specs) {
    bool any = false;
    for (size_t i = 0; i < model.parts.size(); ++i) {
      const auto& p = model.parts[i];
      if (spec.names(p, model.source)) {
        out.push_back(i);
        any = true;
      }
    }
    if (!any)
      throw InputError(file, 0,
                       fmt::format("--ground-part {}{}{}: no part is placed by that line",
                                   spec.file, spec.file.empty() ? "" : ":", spec.line));
  }
  return out;
}

// Moves the bricks `carry` marks into the carried parts, as `role`; loads on them are dropped.
void carry_bricks(Audit& audit, const std::vector<char>& carry, PartRole role) {
  auto& conversion = audit.conversion;
  Assembly& a = conversion.assembly;
  std::vector<Brick> bricks;
  std::vector<size_t> brick_part;
  std::vector<int> index(a.bricks.size(), -1);
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    const Brick& b = a.bricks[i];
    if (!carry[i]) {
      index[i] = int(bricks.size());
      bricks.push_back(b);
      brick_part.push_back(conversion.brick_part[i]);
      continue;
    }
    a.carried.push_back(carried_part(*b.type, role, b.color, b.source, model_pose(b)));
    conversion.carried_part.push_back(conversion.brick_part[i]);
  }
  a.bricks = std::move(bricks);
  conversion.brick_part = std::move(brick_part);
  std::vector<ExternalLoad> loads;
  for (ExternalLoad load : a.loads)
    if (load.brick >= 0 && index[size_t(load.brick)] >= 0) {
      load.brick = index[size_t(load.brick)];
      loads.push_back(load);
    }
  a.loads = std::move(loads);
}

// docs/what-it-analyses.md, turned lattices: a part on a turned frame is analysed there where it
// snaps to another part of that frame; alone on its lattice it is carried, as any part at an angle.
void carry_lone_turned(Audit& audit, const physics::StabilityOptions& o) {
  const Assembly& a = audit.conversion.assembly;
  if (std::none_of(a.bricks.begin(), a.bricks.end(), [](const Brick& b) { return b.frame; }))
    return;
  const auto graph = physics::ContactGraph::connections(a, o.ground, o.budget);
  std::vector<char> alone(a.bricks.size(), 0);
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    if (!a.bricks[i].frame) continue;
    alone[i] = 1;
    for (int k : graph.contacts_of[i]) {
      const auto& c = graph.contacts[size_t(k)];
      if (c.snap() && c.lower != physics::kGround) alone[i] = 0;
    }
  }
  carry_bricks(audit, alone, PartRole::TurnedOffQuarter);
}

// The assembly's contact graph, and per brick whether it reaches no ground (PHYSICS.md
// "Floating").
struct Floating {
  physics::ContactGraph graph;
  std::vector<char> bricks;
};
Floating floating_bricks(const Assembly& a, const physics::StabilityOptions& o) {
  Floating out{physics::ContactGraph::connections(a, o.ground, o.budget),
               std::vector<char>(a.bricks.size(), 0)};
  for (int b : physics::analyze_connectivity(int(a.bricks.size()), out.graph).floating)
    out.bricks[size_t(b)] = 1;
  return out;
}

// Parts that only a joint of another part can hold (a bar, a wheel): those of `kind` that no
// shaft joint ties to a part of another kind, directly or through others of the kind (a tyre
// through its wheel), are held by what the analysis does not model: carried, as `role`.
// Returns whether any was.
bool carry_held_by_no_joint(Audit& audit, const physics::ContactGraph& graph,
                            const std::function<bool(const BrickType&)>& kind, PartRole role) {
  const Assembly& a = audit.conversion.assembly;
  std::vector<char> loose(a.bricks.size(), 0);
  bool any = false;
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    loose[i] = kind(*a.bricks[i].type);
    any = any || loose[i];
  }
  if (!any) return false;
  auto of_kind = [&](int b) { return b != physics::kGround && kind(*a.bricks[size_t(b)].type); };
  for (bool changed = true; changed;) {
    changed = false;
    for (int k : graph.shaft_joints) {
      const auto& c = graph.contacts[size_t(k)];
      for (auto [x, y] : {std::pair(c.lower, c.upper), std::pair(c.upper, c.lower)})
        if (of_kind(x) && loose[size_t(x)] && (!of_kind(y) || !loose[size_t(y)]))
          loose[size_t(x)] = 0, changed = true;
    }
  }
  if (std::find(loose.begin(), loose.end(), 1) == loose.end()) return false;
  carry_bricks(audit, loose, role);
  return true;
}

// A part held by bars alone (a lightsaber blade, a flag's pole) is analysed through the clips
// that hold them. Where no clip does, what holds it (a minifigure's hand, a hollow stud, a tyre on
// it as an axle) is not modelled: it is carried, with its weight.
bool bars_only(const BrickType& t) {
  const PartShape& shape = t.shape;
  return shape.studs.empty() && shape.receptacles.empty() && !shape.shafts.empty() &&
         std::all_of(shape.shafts.begin(), shape.shafts.end(),
                     [](const Shaft& s) { return s.kind == Shaft::Kind::Bar; });
}

// A wheel turns on the pin or axle in its hub, its tyre held by its rim. A wheel that its file's
// holder does not hold by a pin or an axle we derive (a wheel centre's stub axles in a plate's
// wheel clips), and the tyre on it, are carried as before wheels were analysed: on the ground,
// they hold what they touch as the ground does.
bool wheel_or_tyre(const BrickType& t) {
  return t.rolls;
}

// PHYSICS.md: a part placed off the stud lattice is carried. Where a part's studs and receptacles
// meet nothing that stands, that is what happened to it (an ornament on a half-stud offset, a
// door on its hinge pins, a roof whose supports are carried): such parts become carried, and
// whether they touch what stands decides if they are held or float. A hinge or turntable half
// among them that touches its other half, standing, is what holds the rest: it turns on that
// half, so it is carried as PHYSICS.md carries hinges, a joint between what it touches, and what
// hangs on it stands through it (the tower crane's arm on its turntable).
void carry_unconnected(Audit& audit, const physics::StabilityOptions& o) {
  const Assembly& a = audit.conversion.assembly;
  Floating now = floating_bricks(a, o);
  if (carry_held_by_no_joint(audit, now.graph, bars_only, PartRole::BarUnclipped))
    now = floating_bricks(a, o);
  if (carry_held_by_no_joint(audit, now.graph, wheel_or_tyre, PartRole::WheelOnNothing))
    now = floating_bricks(a, o);
  if (std::find(now.bricks.begin(), now.bricks.end(), 1) == now.bricks.end()) return;
  auto floating_now = [&](const Assembly& moved) { return floating_bricks(moved, o).bricks; };
  if (nudge_onto_the_lattice(audit.conversion, now.bricks, floating_now))
    now = floating_bricks(a, o);
  // Technic parts held by nothing but their pins, axles and holes, where those meet nothing that
  // stands, are carried first: carried, they still join what they touch, and what hangs on them
  // may stand through them (a mast of connectors and axles whose holes are not all found).
  std::vector<char> shafts_only(a.bricks.size(), 0);
  bool technic = false;
  for (size_t i = 0; i < a.bricks.size(); ++i) {
    const PartShape& shape = a.bricks[i].type->shape;
    shafts_only[i] = now.bricks[i] && shape.studs.empty() && shape.receptacles.empty();
    technic = technic || shafts_only[i];
  }
  if (technic) {
    carry_bricks(audit, shafts_only, PartRole::ShaftsMeetNothing);
    now = floating_bricks(a, o);
  }
  const physics::ContactGraph& graph = now.graph;
  std::vector<char>& floating = now.bricks;
  std::vector<char> pivots(a.bricks.size(), 0);
  bool any = false;
  // Its other half, standing: a hinge turns on a hinge, a turntable top on its base.
  auto holds = [&](int b) {
    return b != physics::kGround && !floating[size_t(b)] && a.bricks[size_t(b)].type->pivots;
  };
  auto turns_on = [&](int x, int y) {  // x, floating, turns on y
    if (x == physics::kGround || !floating[size_t(x)] || !a.bricks[size_t(x)].type->pivots ||
        !holds(y))
      return;
    pivots[size_t(x)] = 1;
    any = true;
  };
  for (const auto& c : graph.contacts) turns_on(c.lower, c.upper), turns_on(c.upper, c.lower);
  for (const auto& [x, y] : graph.overlaps) turns_on(x, y), turns_on(y, x);
  if (any) {
    carry_bricks(audit, pivots, PartRole::TurnsOnItsHalf);
    floating = floating_bricks(a, o).bricks;
  }
  carry_bricks(audit, floating, PartRole::MeetsNothing);
}

// A part snapped to nothing that stands, resting where it cannot stay (a hinge plate held by its
// fingers, a flap on a clip), is held by a connection the analysis does not model: it is carried
// too. Parts snapped into the structure that nothing can hold stay as they are: "no equilibrium"
// then says so, with them named. Returns whether any part moved.
bool carry_resting_unbalanced(Audit& audit) {
  const auto& r = audit.stability;
  if (r.status != physics::StabilityStatus::NoEquilibrium || r.unbalanced.empty()) return false;
  const auto& c = r.connectivity;
  std::vector<char> anchored(size_t(c.component_count), 0);
  auto ground = [&](int b) { return b == physics::kGround || r.graph.fixed[size_t(b)]; };
  // Snapped or joined to the ground or a fixed part, or standing on it: a model that tips over on
  // the table (a car on its tyres) has no equilibrium, it is not a part resting out of place.
  for (const auto& contact : r.graph.contacts) {
    if (ground(contact.lower) && !ground(contact.upper))
      anchored[size_t(c.component[size_t(contact.upper)])] = 1;
    if ((contact.snap() || contact.joint) && ground(contact.upper) && !ground(contact.lower))
      anchored[size_t(c.component[size_t(contact.lower)])] = 1;
  }
  std::vector<char> resting(size_t(c.component_count), 0);
  bool any = false;
  for (int b : r.unbalanced)
    if (const int k = c.component[size_t(b)]; k >= 0 && !anchored[size_t(k)])
      resting[size_t(k)] = 1, any = true;
  if (!any) return false;
  std::vector<char> carry(audit.conversion.assembly.bricks.size(), 0);
  for (size_t i = 0; i < carry.size(); ++i)
    carry[i] = c.component[i] >= 0 && resting[size_t(c.component[i])];
  carry_bricks(audit, carry, PartRole::RestsOutOfPlace);
  return true;
}

// On a lattice tilted off the vertical gravity pulls across the studs, and a contact's support
// force (one, at its centre) cannot hold the twist that makes about them: where no equilibrium
// holds a part of such a lattice (the corpus's small shuttle: a tail fin on two studs, its engine
// tilted 45 degrees), the lattice is carried as a part at an angle is. Returns whether any was.
bool carry_tilted_unbalanced(Audit& audit) {
  const auto& r = audit.stability;
  if (r.status != physics::StabilityStatus::NoEquilibrium) return false;
  const auto& bricks = audit.conversion.assembly.bricks;
  std::vector<int> lattices;
  for (int b : r.unbalanced)
    if (bricks[size_t(b)].frame && tilted(*bricks[size_t(b)].frame))
      lattices.push_back(bricks[size_t(b)].frame->id);
  if (lattices.empty()) return false;
  std::vector<char> carry(bricks.size(), 0);
  for (size_t i = 0; i < bricks.size(); ++i)
    carry[i] = bricks[i].frame &&
               std::find(lattices.begin(), lattices.end(), bricks[i].frame->id) != lattices.end();
  carry_bricks(audit, carry, PartRole::OnTiltedLattice);
  return true;
}

// Times of an earlier analysis added to a later one's.
void add_times(physics::LpStats& to, const physics::LpStats& from) {
  to.graph_seconds += from.graph_seconds;
  to.build_seconds += from.build_seconds;
  to.solve_seconds += from.solve_seconds;
  to.capacity_seconds += from.capacity_seconds;
}

// A part left out has no body, but by LDraw's convention its origin is its top: one at or below
// the lowest face of everything known reaches at least a plate lower, and the ground is taken
// there, so that nothing is taken to stand on the ground when it stands on an unknown part. A
// missing submodel's origin is wherever its author put it (a tree's, a street lamp's at its
// foot): it moves no ground, or a town whose one lamp file is missing would float whole.
void lower_ground_under_unknown_parts(Audit& audit) {
  Assembly& a = audit.conversion.assembly;
  if (audit.conversion.skipped.empty() || a.bricks.empty()) return;
  double lowest = std::numeric_limits<double>::infinity();
  for (const Brick& b : a.bricks)
    for (const Box& box : physics::world_shape(b).body)
      lowest = std::min(lowest, physics::model_bounds(b, box).min[1]);
  for (const CarriedPart& c : a.carried)
    for (const Vec3& p : physics::world_outline(c)) lowest = std::min(lowest, p[1]);
  double ground = lowest;
  for (const auto& s : audit.conversion.skipped) {
    if (s.role == PartRole::Copy || s.role == PartRole::MissingSubmodel) continue;
    const double top = -audit.model.parts[s.part].transform.pos[1] - a.origin_ldu[1];
    if (top <= lowest + 0.5) ground = std::min(ground, top - kLduPerPlate);
  }
  if (ground < lowest) a.ground_height = ground;
}

// What the verdict rests on (report/assumptions.h). Most of the mass carried, a stable verdict
// says little: the model is not judged. With --strict a stable verdict must not rest on what can
// change it: held and unknown parts, and the assumed joints where the model analysed without
// them is not stable.
void judge_assumptions(Audit& audit, const AuditOptions& options) {
  audit.assumptions = assumptions_of(audit);
  Assumptions& as = audit.assumptions;
  if (audit.verdict != Verdict::Stable) return;
  if (as.carried_share() > kMostOfTheMass) {
    audit.verdict = Verdict::NotJudged;
    return;
  }
  if (!options.strict) return;
  if (as.rigid_joints > 0) {
    physics::StabilityOptions without = options.stability;
    without.assumed_joints = false;
    without.brick_capacity = false;
    const physics::StabilityResult r =
        physics::analyze_stability(audit.conversion.assembly, without);
    as.joints_checked = true;
    const size_t floating = r.connectivity.floating.size() + r.connectivity.floating_carried.size();
    if (verdict_of(r, options.min_cm_gf) == Verdict::Stable) {
      as.without_joints = fmt::format("stable without them: C_M = {:.3f} gf", r.cm_gf());
    } else {
      as.without_joints = floating ? fmt::format("without them {} part{} float{}", floating,
                                                 floating == 1 ? "" : "s", floating == 1 ? "s" : "")
                          : r.status == physics::StabilityStatus::Solved
                              ? fmt::format("without them C_M = {:.3f} gf", r.cm_gf())
                              : fmt::format("without them: {}", physics::to_string(r.status));
      for (Assumption& j : joint_assumptions(audit)) {
        j.text += " (" + as.without_joints + ")";
        as.deciding.push_back(std::move(j));
      }
    }
  }
  if (!as.deciding.empty()) audit.verdict = Verdict::StableByAssumption;
}

// Why a step does not stand, naming its parts: those that float, else those no forces balance,
// else the two that the weakest contact joins.
void explain_falling_step(const Audit& audit, const physics::StabilityResult& r,
                          const std::vector<int>& whole_index,
                          const std::vector<int>& whole_carried_index, double min_cm_gf,
                          StepAudit& s) {
  auto name = [&](const std::vector<int>& partial_bricks, const std::vector<int>& partial_carried,
                  const std::string& what) {
    for (int b : partial_bricks) s.culprits.push_back(whole_index[size_t(b)]);
    for (int c : partial_carried) s.carried_culprits.push_back(whole_carried_index[size_t(c)]);
    std::vector<std::string> shown;
    for (size_t k = 0; k < s.culprits.size() && shown.size() < kPartsNamed; ++k)
      shown.push_back(describe_brick(audit, s.culprits[k]));
    for (size_t k = 0; k < s.carried_culprits.size() && shown.size() < kPartsNamed; ++k)
      shown.push_back(describe_carried(audit, s.carried_culprits[k]));
    return named_few(shown, s.culprits.size() + s.carried_culprits.size()) + what;
  };
  const auto& floating = r.connectivity.floating;
  const auto& floating_carried = r.connectivity.floating_carried;
  if (!floating.empty() || !floating_carried.empty()) {
    s.why = name(
        floating, floating_carried,
        floating.size() + floating_carried.size() == 1 ? " reaches no ground" : " reach no ground");
  } else if (r.status == physics::StabilityStatus::NoEquilibrium && !r.unbalanced.empty()) {
    s.why = name(r.unbalanced, {}, ": no forces hold it up (it tips or hangs)");
  } else if (r.status == physics::StabilityStatus::Solved && !r.weakest.empty()) {
    std::vector<int> pair;
    for (int b : {r.weakest.front().lower, r.weakest.front().upper})
      if (b >= 0) pair.push_back(b);
    s.why = fmt::format("C_M {:.3f} gf, not above {:g}; the weakest contact: {}", s.cm_gf,
                        min_cm_gf, name(pair, {}, ""));
  } else {
    s.why = physics::to_string(r.status);
  }
}

// One step's judgement: the bricks and carried parts of `from` that `placed` takes (by their
// source and their index into its model's parts), on the table they are built on when
// `on_table` (resting at their lowest point, nothing holding their knobs), else on the finished
// model's ground with the loads on what is placed. With `start`, a certificate begun from those
// forces decides it when it shows the step standing (physics/step_stability.h); `forces` then
// receives the certificate's.
StepAudit judge_step(const Audit& from, int step,
                     const std::function<bool(const SourceRef&, size_t part)>& placed,
                     bool on_table, const AuditOptions& options, const physics::StepForces* start,
                     physics::StepForces* forces) {
  const Assembly& whole = from.conversion.assembly;
  Assembly partial;
  partial.origin_ldu = whole.origin_ldu;
  if (!on_table) {
    partial.ground_height = from.stability.graph.ground_height;
    partial.ground_slope = from.stability.graph.ground_slope;
  }
  std::vector<int> index(whole.bricks.size(), -1), whole_index, whole_carried_index;
  for (int i = 0; i < int(whole.bricks.size()); ++i)
    if (placed(whole.bricks[size_t(i)].source, from.conversion.brick_part[size_t(i)])) {
      index[size_t(i)] = int(partial.bricks.size());
      whole_index.push_back(i);
      partial.bricks.push_back(whole.bricks[size_t(i)]);
    }
  for (int i = 0; i < int(whole.carried.size()); ++i)
    if (placed(whole.carried[size_t(i)].source, from.conversion.carried_part[size_t(i)])) {
      whole_carried_index.push_back(i);
      partial.carried.push_back(whole.carried[size_t(i)]);
    }
  for (const auto& load : whole.loads)
    if (!on_table && index[size_t(load.brick)] >= 0)
      partial.loads.push_back(
          {index[size_t(load.brick)], load.force_n, load.spread_over_top_knobs, load.point});
  StepAudit s;
  s.step = step;
  s.bricks = int(partial.bricks.size());
  if (partial.bricks.empty() && partial.carried.empty()) {
    s.stable = true;
    return s;
  }
  physics::StabilityOptions stability = options.stability;
  if (on_table) stability.ground = physics::GroundMode::Table;
  // Built on the finished model's ground, a step's contacts are the model's among its parts
  // where those are pairs (legolize's outputs: no carried parts); else searched for in the
  // step's model.
  const physics::ContactGraph& model_graph = from.stability.graph;
  const bool from_model = !on_table && model_graph.contacts_of.size() == whole.bricks.size() &&
                          physics::steps_take_contacts_from(model_graph);
  physics::StepStability analysed = physics::analyze_step(
      partial,
      physics::prepare_step(partial, whole_index, stability, from_model ? &model_graph : nullptr),
      start ? *start : physics::StepForces{}, stability,
      start ? std::optional<double>(options.min_cm_gf) : std::nullopt);
  const physics::StabilityResult& r = analysed.result;
  s.status = r.status;
  s.cm_gf = r.cm_gf();
  s.certified = r.certified;
  s.floating = int(r.connectivity.floating.size() + r.connectivity.floating_carried.size());
  const Verdict v = verdict_of(r, options.min_cm_gf);
  s.stable = v == Verdict::Stable || v == Verdict::NothingToAnalyse;
  if (forces) *forces = std::move(analysed.forces);
  if (!s.stable)
    explain_falling_step(from, r, whole_index, whole_carried_index, options.min_cm_gf, s);
  return s;
}

// The model after `step`: its bricks and carried parts up to then, judged by judge_step. A step
// that builds a sub-assembly apart (a submodel with steps of its own) judges it alone, as built
// so far, on the table, and one that builds aside in MLCad's buffers judges what its view shows
// of Audit::aside so; the model in place is as the step before left it. `start`, `forces`: as
// judge_step's, for the model in place (a sub-assembly's step begins from no forces there).
StepAudit audit_step(const Audit& audit, int step, const AuditOptions& options,
                     const physics::StepForces* start, physics::StepForces* forces) {
  const auto& steps = audit.model.steps;  // steps[k] is step k + 1
  if (audit.aside && step >= 1 && step <= int(steps.size()) &&
      !steps[size_t(step - 1)].aside_shown.empty()) {
    const std::vector<int>& shown = steps[size_t(step - 1)].aside_shown;  // ascending
    StepAudit s = judge_step(
        *audit.aside, step,
        [&](const SourceRef&, size_t part) {
          return std::binary_search(shown.begin(), shown.end(), int(part));
        },
        /*on_table=*/true, options, nullptr, nullptr);
    s.built_aside = true;
    return s;
  }
  const Assembly& whole = audit.conversion.assembly;
  const SourceRef* apart = nullptr;
  for (const Brick& b : whole.bricks)
    if (b.source.built_in == step) apart = &b.source;
  for (const CarriedPart& c : whole.carried)
    if (!apart && c.source.built_in == step) apart = &c.source;
  auto placed = [&](const SourceRef& s, size_t) {
    if (!apart) return s.step <= step;
    return s.apart_from == apart->apart_from && s.step == apart->step && s.built_in > 0 &&
           s.built_in <= step;
  };
  StepAudit s = judge_step(audit, step, placed, apart != nullptr, options, start, forces);
  s.apart = apart != nullptr;
  return s;
}

// Every step, two at a time, within --max-seconds. Step k is certified from the forces of the
// latest step before k - 1 that has them (the other worker is on k - 1): waiting for those steps
// keeps the start, and so the report, the same whatever the timing (beginning from whichever step
// had finished made a step's C_M a certificate's bound in one run and the LP's in another); the
// LP decides the steps no certificate covers, and gives the weakest step's C_M.
void audit_steps(Audit& audit, const AuditOptions& given) {
  AuditOptions options = given;
  options.stability.block_jobs = 1;  // the steps are analysed two at a time already
  int last = 0;
  for (const Brick& b : audit.conversion.assembly.bricks) last = std::max(last, b.source.step);
  for (const CarriedPart& c : audit.conversion.assembly.carried)
    last = std::max(last, c.source.step);
  for (const ldraw::Step& st : audit.model.steps)
    if (!st.aside_shown.empty()) last = std::max(last, st.number);
  std::vector<StepAudit> analysed(static_cast<size_t>(std::max(last, 0)));
  std::vector<char> done(analysed.size(), 0);
  std::vector<std::shared_ptr<const physics::StepForces>> forces_of(analysed.size());
  static const physics::StepForces kNoForces;  // a certificate from no forces at all
  std::atomic<int> next{0};
  std::mutex mutex;
  std::condition_variable finished;  // a step done, or a worker stopped
  int done_before = 0;               // steps 0 .. done_before - 1 are all done
  int released = 0;                  // forces_of[0 .. released - 1] are let go
  bool stopped = false;
  // The steps' budget (audit_file's): a step it runs out in is left unchecked.
  const Budget* budget = options.stability.budget;
  auto in_time = [&] { return !budget || !budget->spent(); };
  auto work = [&] {
    for (int k; in_time() && (k = next++) < last;) {
      std::shared_ptr<const physics::StepForces> from;
      {
        std::unique_lock lock(mutex);
        finished.wait(lock, [&] { return stopped || done_before >= k - 1; });
        if (stopped) return;
        for (int j = k - 2; j >= 0 && !from; --j) from = forces_of[size_t(j)];
      }
      physics::StepForces forces;
      try {
        analysed[size_t(k)] =
            audit_step(audit, k + 1, options, from ? from.get() : &kNoForces, &forces);
      } catch (const OutOfTime&) {
        const std::lock_guard lock(mutex);
        stopped = true;
        finished.notify_all();
        return;
      }
      const std::lock_guard lock(mutex);
      done[size_t(k)] = 1;
      if (!forces.empty())
        forces_of[size_t(k)] = std::make_shared<const physics::StepForces>(std::move(forces));
      while (done_before < last && done[size_t(done_before)]) ++done_before;
      // Every step not done yet begins from the latest forces before done_before - 1 or later:
      // those before them are let go (with the LP's spread they hold, tens of MB each on a large
      // sculpture: legolize's bunny at height 40 peaked at 1.27 GB with them kept, 487 MB before
      // the spreads).
      int latest = done_before - 2;
      while (latest >= 0 && !forces_of[size_t(latest)]) --latest;
      for (; released < latest; ++released) forces_of[size_t(released)].reset();
      finished.notify_all();
    }
    // Out of steps or of time: a worker waiting for this one's step must not wait for more.
    const std::lock_guard lock(mutex);
    if (!in_time()) stopped = true;
    finished.notify_all();
  };
  {
    std::thread second(work);
    work();
    second.join();
  }
  // The weakest step's C_M exactly (physics::solve_weakest_again).
  for (int solves = 0; in_time(); ++solves) {
    int weakest = -1;
    std::vector<physics::StepMargin> margins;
    for (int k = 0; k < last; ++k)
      if (done[size_t(k)] && analysed[size_t(k)].stable && analysed[size_t(k)].bricks > 0) {
        margins.push_back({analysed[size_t(k)].cm_gf, analysed[size_t(k)].certified});
        if (weakest < 0 || analysed[size_t(k)].cm_gf < analysed[size_t(weakest)].cm_gf) weakest = k;
      }
    if (weakest < 0 || !analysed[size_t(weakest)].certified ||
        !physics::solve_weakest_again(margins, solves))
      break;
    try {
      analysed[size_t(weakest)] = audit_step(audit, weakest + 1, options, nullptr, nullptr);
    } catch (const OutOfTime&) {
      break;  // the certificate stands
    }
  }
  for (int step = 1; step <= last; ++step) {
    if (!done[size_t(step - 1)]) {
      audit.unchecked_from_step = step;
      break;
    }
    StepAudit& s = analysed[size_t(step - 1)];
    if (step <= int(audit.model.steps.size())) s.aside = audit.model.steps[size_t(step - 1)].aside;
    if (s.bricks == 0 && s.status == physics::StabilityStatus::Empty && s.stable) continue;
    if (!s.stable && !audit.first_failing_step) audit.first_failing_step = step;
    audit.steps.push_back(s);
  }
  if (audit.first_failing_step && audit.verdict == Verdict::Stable)
    audit.verdict = Verdict::Unstable;
  else if (audit.unchecked_from_step && audit.verdict == Verdict::Stable)
    audit.verdict = Verdict::Undecided;
}

}  // namespace

bool LineSpec::names(const ldraw::PlacedPart& part, const std::string& model_file) const {
  if (part.line != line) return false;
  if (file.empty()) return part.file == model_file;
  return std::filesystem::path(part.file).filename() == file || part.file == file;
}

LineSpec parse_line_spec(const std::string& text, const std::string& option) {
  LineSpec spec;
  const auto colon = text.rfind(':');
  const std::string_view number = colon == std::string::npos
                                      ? std::string_view(text)
                                      : std::string_view(text).substr(colon + 1);
  auto line = whole_number(number);
  if (!line || *line == 0 || (colon != std::string::npos && colon == 0))
    throw InputError("", 0,
                     fmt::format("{} '{}': expected LINE or FILE:LINE (a line number "
                                 "from 1)",
                                 option, text.size() > 80 ? text.substr(0, 80) + "..." : text));
  spec.line = *line;
  if (colon != std::string::npos) spec.file = text.substr(0, colon);
  return spec;
}

LoadSpec parse_load_spec(const std::string& text) {
  const std::string shown = text.size() > 80 ? text.substr(0, 80) + "..." : text;
  auto fail = [&](const std::string& why) {
    return InputError("", 0,
                      fmt::format("--load '{}': {}; expected LINE=GRAMS, FILE:LINE=GRAMS, "
                                  "step:K=GRAMS, submodel:NAME=GRAMS or top=GRAMS",
                                  shown, why));
  };
  const auto equals = text.rfind('=');
  if (equals == std::string::npos || equals == 0) throw fail("no '=GRAMS'");
  const std::string target = text.substr(0, equals), grams = text.substr(equals + 1);
  LoadSpec spec;
  spec.text = text;
  double g = 0;
  auto [p, ec] = std::from_chars(grams.data(), grams.data() + grams.size(), g);
  if (grams.empty() || ec != std::errc() || p != grams.data() + grams.size() || !std::isfinite(g) ||
      g < 0)
    throw fail("the weight must be a finite number of grams, 0 or more");
  if (g > physics::kMaxLoadGrams)
    throw fail(
        fmt::format("the weight must be at most {:.0f} grams (a tonne)", physics::kMaxLoadGrams));
  spec.grams = g;
  if (target == "top") {
    spec.target = LoadSpec::Target::Top;
  } else if (target.starts_with("step:")) {
    spec.target = LoadSpec::Target::Step;
    auto k = whole_number(std::string_view(target).substr(5));
    if (!k) throw fail("the step must be a whole number");
    spec.number = *k;
  } else if (target.starts_with("submodel:")) {
    spec.target = LoadSpec::Target::Submodel;
    spec.name = target.substr(9);
    if (spec.name.empty()) throw fail("no submodel name");
  } else {
    try {
      spec.line = parse_line_spec(target, "--load");
    } catch (const InputError&) {
      throw fail("the line must be a whole number from 1");
    }
  }
  return spec;
}

const ldraw::PlacedPart& placed_part(const Audit& audit, int brick) {
  return audit.model.parts[audit.conversion.brick_part[size_t(brick)]];
}

std::string describe_brick(const Audit& audit, int brick) {
  if (brick == physics::kGround) return "the ground";
  const Brick& b = audit.conversion.assembly.bricks[size_t(brick)];
  const auto& pos = placed_part(audit, brick).transform.pos;
  return fmt::format("{}:{} {} {} at ({:g}, {:g}, {:g})",
                     one_line(std::filesystem::path(b.source.file).filename().string()),
                     b.source.line, b.type->part, audit.model.color_table.name(b.color), pos[0],
                     pos[1], pos[2]);
}

std::string describe_carried(const Audit& audit, int carried) {
  const CarriedPart& c = audit.conversion.assembly.carried[size_t(carried)];
  const auto& pos = audit.model.parts[audit.conversion.carried_part[size_t(carried)]].transform.pos;
  return fmt::format("{}:{} {} {} at ({:g}, {:g}, {:g})",
                     one_line(std::filesystem::path(c.source.file).filename().string()),
                     c.source.line, c.part, audit.model.color_table.name(c.color), pos[0], pos[1],
                     pos[2]);
}

int turned_lattice_bricks(const Assembly& assembly) {
  return int(std::count_if(assembly.bricks.begin(), assembly.bricks.end(),
                           [](const Brick& b) { return b.frame.has_value(); }));
}

namespace {

// The audit of audit_file, within `options`' budget: it throws OutOfTime when that is spent.
// The memory budget's measure: a 100,000-part Datsville town peaks at 1.26 GB (12.6 kB a part,
// docs/performance.md), rounded up.
constexpr double kBytesPerPart = 16 << 10;

// The model's parts as the analysis takes them: bricks where they snap, carried, or left out.
void convert_parts(Audit& audit, const AuditOptions& options, parts::PartLibrary& library) {
  audit.conversion = parts::to_assembly(audit.model, library,
                                        fixed_parts(audit.model, options.ground_parts, audit.file),
                                        options.stability.budget);
  take_onto_the_plates(audit.conversion);
  lower_ground_under_unknown_parts(audit);
  carry_lone_turned(audit, options.stability);
  carry_unconnected(audit, options.stability);
}

void audit_within(Audit& audit, const AuditOptions& options, parts::PartLibrary& library) {
  auto start = std::chrono::steady_clock::now();
  audit.model = ldraw::read_file(audit.file, options.read);
  audit.parse_seconds = seconds_since(start);
  for (const auto& d : audit.model.diagnostics)
    if (d.severity == ldraw::Severity::Error) {
      audit.fatal = d.text();
      return;
    }
  if (audit.model.parts.empty()) {
    audit.fatal = fmt::format("{}: error: no part in the model", audit.file);
    return;
  }
  if (const std::string why =
          memory_shortfall(double(audit.model.parts.size()) * kBytesPerPart,
                           fmt::format("a model of {} parts", audit.model.parts.size()));
      !why.empty())
    throw OutOfMemory("out of memory: " + why);
  start = std::chrono::steady_clock::now();
  convert_parts(audit, options, library);
  if (options.steps && !audit.model.aside.empty()) {
    audit.aside = std::make_unique<Audit>();
    Audit& aside = *audit.aside;
    aside.file = audit.file;
    aside.model = audit.model;
    aside.model.parts = std::move(aside.model.aside);
    aside.model.aside.clear();
    AuditOptions on_the_table = options;
    on_the_table.ground_parts.clear();
    on_the_table.stability.ground = physics::GroundMode::Table;
    convert_parts(aside, on_the_table, library);
  }
  audit.parts_seconds = seconds_since(start);
  if (audit.conversion.assembly.bricks.empty()) {
    audit.verdict = Verdict::NothingToAnalyse;
    audit.assumptions = assumptions_of(audit);
    return;
  }
  audit.load_notes = apply_loads(audit, options.loads);
  // The report's times are the run's: an analysis that named parts to carry often costs the most
  // (its diagnosis: the carriage house 3.2 s of 4.6).
  physics::StabilityOptions stability = with_capacity(options.stability, options.brick_capacity);
  stability.diagnose_turning = false;  // once, of the last analysis
  // An analysis after parts are carried solves again only the structures that changed.
  physics::SolvedBlocks solved;
  stability.solved_blocks = &solved;
  auto analyse = [&] {
    const physics::LpStats before = audit.stability.stats;
    audit.stability = physics::analyze_stability(audit.conversion.assembly, stability);
    if (audit.analyses++ > 0) add_times(audit.stability.stats, before);
  };
  analyse();
  if (carry_tilted_unbalanced(audit)) analyse();
  if (carry_resting_unbalanced(audit)) analyse();
  audit.stability.turning =
      physics::turning_joints(audit.conversion.assembly, audit.stability, stability);
  audit.verdict = verdict_of(audit.stability, options.min_cm_gf);
}

}  // namespace

Audit audit_file(const std::filesystem::path& path, const AuditOptions& options,
                 parts::PartLibrary& library) {
  Audit audit;
  audit.file = path.string();
  // --max-seconds bounds every stage of the file's audit; its build steps get as long again.
  const Budget budget(options.stability.max_seconds, options.progress);
  AuditOptions within = options;
  within.read.budget = &budget;
  within.stability.budget = &budget;
  std::optional<Budget> steps;
  try {
    audit_within(audit, within, library);
    if (!audit.fatal.empty() || audit.verdict == Verdict::NothingToAnalyse) return audit;
    if (options.steps) {
      within.stability.budget = &steps.emplace(options.stability.max_seconds, options.progress);
      audit_steps(audit, within);
    }
    judge_assumptions(audit, within);
  } catch (const OutOfTime& e) {
    audit.verdict = Verdict::Undecided;
    audit.out_of_time = e.what();
  } catch (const OutOfMemory& e) {
    audit.verdict = Verdict::Undecided;
    audit.out_of_memory = e.what();
  } catch (const std::bad_alloc&) {
    audit.verdict = Verdict::Undecided;
    audit.out_of_memory = "out of memory: an allocation failed";
  }
  return audit;
}

}  // namespace lego::report
