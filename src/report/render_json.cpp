#include <filesystem>

#include "ldraw/writer.h"

#include "report/render.h"

namespace lego::report {
namespace {

using nlohmann::json;

json brick_json(const Audit& a, int brick) {
  if (brick == physics::kGround) return {{"ground", true}, {"part", "baseplate"}};
  const Brick& b = a.conversion.assembly.bricks[size_t(brick)];
  const auto& pos = placed_part(a, brick).transform.pos;
  return {{"file", b.source.file},
          {"line", b.source.line},
          {"part", b.type->part},
          {"color", b.color},
          {"position", {pos[0], pos[1], pos[2]}}};
}

json carried_json(const Audit& a, int carried) {
  const CarriedPart& c = a.conversion.assembly.carried[size_t(carried)];
  const auto& pos = a.model.parts[a.conversion.carried_part[size_t(carried)]].transform.pos;
  return {{"file", c.source.file},
          {"line", c.source.line},
          {"part", c.part},
          {"color", c.color},
          {"position", {pos[0], pos[1], pos[2]}}};
}

json number_or_null(bool valid, double v) {
  return valid ? json(v) : json(nullptr);
}

// What became of the placed parts: counts, carried and left-out parts, part kinds learnt from
// the library, and what reading said.
void parts_json(const Audit& a, json& j) {
  j["title"] = a.model.title;
  j["main_model"] = a.model.main_block;
  j["parts"] = a.model.parts.size();
  j["bricks"] = a.conversion.assembly.bricks.size();  // analysed as structure
  j["turned"] = turned_lattice_bricks(a.conversion.assembly);
  j["carried"] = json::array();
  for (size_t i = 0; i < a.conversion.assembly.carried.size(); ++i) {
    const CarriedPart& c = a.conversion.assembly.carried[i];
    json entry = carried_json(a, int(i));
    entry["reason"] = carried_because(c.role);
    entry["mass_g"] = c.mass_g;
    j["carried"].push_back(entry);
  }
  j["skipped"] = json::array();
  for (const auto& s : a.conversion.skipped) {
    const auto& p = a.model.parts[s.part];
    j["skipped"].push_back(
        {{"file", p.file}, {"line", p.line}, {"part", p.part}, {"reason", s.reason}});
  }
  j["learnt_parts"] = json::array();
  for (const auto& t : a.conversion.types->types()) {
    if (BrickCatalog::standard().find(t.part)) continue;
    j["learnt_parts"].push_back({{"part", t.part},
                                 {"name", t.name},
                                 {"kind", t.kind},
                                 {"studs", t.shape.studs.size()},
                                 {"receptacles", t.shape.receptacles.size()},
                                 {"bores", t.shape.bores.size()},
                                 {"body_boxes", t.shape.body.size()},
                                 {"baseplate", t.baseplate},
                                 {"mass_g", t.mass_g},
                                 {"mass_source", t.mass_source}});
  }
  j["diagnostics"] = json::array();
  std::vector<ldraw::Diagnostic> diagnostics = a.model.diagnostics;
  diagnostics.insert(diagnostics.end(), a.conversion.diagnostics.begin(),
                     a.conversion.diagnostics.end());
  for (const auto& d : diagnostics)
    j["diagnostics"].push_back(
        {{"severity", d.severity == ldraw::Severity::Error ? "error" : "warning"},
         {"file", d.file},
         {"line", d.line},
         {"message", d.message}});
}

// The ground, what reaches it, and the joints taken as rigid or turning.
void connections_json(const Audit& a, const AuditOptions& options, json& j) {
  const auto& r = a.stability;
  j["ground"] = options.stability.ground == physics::GroundMode::Table ? "table" : "baseplate";
  j["components"] = r.connectivity.component_count;
  j["touches_ground"] = !r.connectivity.grounded.empty() &&
                        std::find(r.connectivity.grounded.begin(), r.connectivity.grounded.end(),
                                  1) != r.connectivity.grounded.end();
  j["floating"] = json::array();
  for (int b : r.connectivity.floating) j["floating"].push_back(brick_json(a, b));
  j["floating_carried"] = json::array();
  for (int c : r.connectivity.floating_carried) j["floating_carried"].push_back(carried_json(a, c));
  j["fixed"] = json::array();
  for (size_t b = 0; b < r.graph.fixed.size(); ++b)
    if (r.graph.fixed[b]) j["fixed"].push_back(brick_json(a, int(b)));
  j["joints"] = json::array();
  for (const auto& group : r.graph.carried_groups) {
    if (!group.assumed_joint()) continue;
    json through = json::array(), joins = json::array();
    for (int c : group.carried) through.push_back(carried_json(a, c));
    for (int b : group.joins) joins.push_back(brick_json(a, b));
    j["joints"].push_back({{"through", through}, {"joins", joins}});
  }
  // Where two lattices or two hinge halves touch, nothing is carried through: "through" is empty.
  std::vector<int> touching = r.graph.lattice_joints;
  touching.insert(touching.end(), r.graph.pivot_joints.begin(), r.graph.pivot_joints.end());
  for (int k : touching) {
    const auto& c = r.graph.contacts[size_t(k)];
    j["joints"].push_back(
        {{"through", json::array()},
         {"joins", json::array({brick_json(a, c.lower), brick_json(a, c.upper)})}});
  }
  j["technic_joints"] = json::array();
  for (int k : r.graph.shaft_joints) {
    const auto& c = r.graph.contacts[size_t(k)];
    j["technic_joints"].push_back(
        {{"kind", c.joint_kind == physics::Contact::Kind::Holds ? "holds" : "turns"},
         {"a", brick_json(a, c.lower)},
         {"b", brick_json(a, c.upper)}});
  }
  j["turning"] = json::array();
  for (const auto& [k, moment] : r.turning) {
    const auto& c = r.graph.contacts[size_t(k)];
    j["turning"].push_back({{"a", brick_json(a, c.lower)},
                            {"b", brick_json(a, c.upper)},
                            {"moment_gf_stud", moment / physics::kGravity}});
  }
}

// What the verdict rests on (report/assumptions.h), and --strict's judgement of it.
void assumptions_json(const Audit& a, const AuditOptions& options, json& j) {
  const Assumptions& as = a.assumptions;
  json deciding = json::array();
  for (const Assumption& d : as.deciding)
    deciding.push_back({{"kind", d.kind == Assumption::Kind::Joint  ? "joint"
                                 : d.kind == Assumption::Kind::Held ? "held"
                                                                    : "unknown"},
                        {"text", d.text}});
  j["assumptions"] = {{"analysed", as.analysed},
                      {"carried", as.carried},
                      {"left_out", as.left_out},
                      {"analysed_mass_g", as.analysed_mass_g},
                      {"carried_mass_g", as.carried_mass_g},
                      {"carried_mass_share", as.carried_share()},
                      {"rigid_joints", as.rigid_joints},
                      {"joints_checked", as.joints_checked},
                      {"without_joints", as.joints_checked ? json(as.without_joints) : json()},
                      {"deciding", deciding}};
  if (options.strict)
    j["strict"] = {{"passes", a.verdict == Verdict::Stable}, {"reasons", deciding}};
}

// The analysis: status, C_M, the weakest contacts, the structures solved apart, the LP.
void stability_json(const Audit& a, const AuditOptions& options, json& j) {
  const auto& r = a.stability;
  const bool solved = r.status == physics::StabilityStatus::Solved;
  j["status"] = physics::to_string(r.status);
  j["tips_over"] = r.graph.tips_over;
  j["ground_slope"] = {r.graph.ground_slope[0], r.graph.ground_slope[1]};
  j["unbalanced"] = json::array();
  for (int b : r.unbalanced) j["unbalanced"].push_back(brick_json(a, b));
  j["min_cm_gf"] = options.min_cm_gf;
  j["cm_newton"] = number_or_null(solved, r.cm_newton());
  j["cm_gf"] = number_or_null(solved, r.cm_gf());
  j["weakest"] = json::array();
  for (const auto& w : r.weakest)
    j["weakest"].push_back(
        {{"a", brick_json(a, w.lower)}, {"b", brick_json(a, w.upper)}, {"dual", w.share}});
  j["structures"] = json::array();
  for (const auto& b : r.blocks) {
    const bool cm = b.status == physics::StabilityStatus::Solved;
    json first = b.bricks.empty() ? json(nullptr) : brick_json(a, b.bricks.front());
    if (!b.bricks.empty()) first["submodel"] = placed_part(a, b.bricks.front()).submodel;
    j["structures"].push_back({{"status", physics::to_string(b.status)},
                               {"cm_gf", number_or_null(cm, b.cm_gf())},
                               {"parts", b.bricks.size()},
                               {"structures", b.structures},
                               {"first", first}});
  }
  j["lp"] = {{"rows", r.stats.rows},
             {"columns", r.stats.columns},
             {"nonzeros", r.stats.nonzeros},
             {"iterations", r.stats.iterations},
             {"solver", r.stats.solver.empty() ? json(nullptr) : json(r.stats.solver)},
             {"capacity_solver",
              r.stats.capacity_solver.empty() ? json(nullptr) : json(r.stats.capacity_solver)},
             {"solver_note", r.message.empty() ? json(nullptr) : json(r.message)}};
  j["analyses"] = a.analyses;
  j["timing"] = {{"parse", a.parse_seconds},       {"parts", a.parts_seconds},
                 {"graph", r.stats.graph_seconds}, {"build", r.stats.build_seconds},
                 {"solve", r.stats.solve_seconds}, {"capacity", r.stats.capacity_seconds}};
}

// With --steps: each build step, and the first that does not stand.
void steps_json(const Audit& a, json& j) {
  j["steps"] = json::array();
  for (const auto& s : a.steps) {
    json culprits = json::array();
    const Audit& of = s.built_aside && a.aside ? *a.aside : a;  // whose parts the culprits are
    for (int b : s.culprits) culprits.push_back(brick_json(of, b));
    for (int c : s.carried_culprits) culprits.push_back(carried_json(of, c));
    j["steps"].push_back(
        {{"step", s.step},
         {"bricks", s.bricks},
         {"stable", s.stable},
         {"status", physics::to_string(s.status)},
         {"floating", s.floating},
         {"cm_gf", number_or_null(s.status == physics::StabilityStatus::Solved, s.cm_gf)},
         {"certified", s.certified},
         {"aside_parts", s.aside},
         {"apart", s.apart},
         {"built_aside", s.built_aside},
         {"why", s.stable ? json(nullptr) : json(s.why)},
         {"parts", culprits}});
  }
  j["first_failing_step"] = a.first_failing_step ? json(*a.first_failing_step) : json(nullptr);
  j["unchecked_from_step"] = a.unchecked_from_step ? json(*a.unchecked_from_step) : json(nullptr);
}

}  // namespace

json render_json(const Audit& a, const AuditOptions& options) {
  json j;
  j["file"] = a.file;
  j["verdict"] = a.verdict == Verdict::Stable               ? "stable"
                 : a.verdict == Verdict::Unstable           ? "unstable"
                 : a.verdict == Verdict::Undecided          ? "undecided"
                 : a.verdict == Verdict::NothingToAnalyse   ? "nothing-to-analyse"
                 : a.verdict == Verdict::NotJudged          ? "not-judged"
                 : a.verdict == Verdict::StableByAssumption ? "stable-by-assumption"
                                                            : "unreadable";
  j["stable"] = a.stable();
  if (a.verdict == Verdict::Unreadable) {
    j["error"] = a.fatal;
    return j;
  }
  if (!a.out_of_time.empty()) {  // nothing else is complete
    j["status"] = "out of time";
    j["out_of_time"] = a.out_of_time;
    return j;
  }
  if (!a.out_of_memory.empty()) {
    j["status"] = "out of memory";
    j["out_of_memory"] = a.out_of_memory;
    return j;
  }
  parts_json(a, j);
  connections_json(a, options, j);
  assumptions_json(a, options, j);
  stability_json(a, options, j);
  if (options.steps) steps_json(a, j);
  return j;
}

}  // namespace lego::report
