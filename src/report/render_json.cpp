#include <filesystem>

#include "report/render.h"

namespace lego::report {
namespace {

using nlohmann::json;

json brick_json(const Audit& a, int brick) {
  if (brick == physics::kGround) return {{"ground", true}, {"part", "baseplate"}};
  const Brick& b = a.conversion.assembly.bricks[brick];
  auto t = ldraw::brick_transform(b, a.conversion.assembly.origin_ldu);
  return {{"file", b.source.file},
          {"line", b.source.line},
          {"part", b.type->part},
          {"color", b.color},
          {"position", {t.pos[0], t.pos[1], t.pos[2]}}};
}

json number_or_null(bool valid, double v) {
  return valid ? json(v) : json(nullptr);
}

}  // namespace

json render_json(const Audit& a, const AuditOptions& options) {
  const auto& r = a.stability;
  const bool solved = r.status == physics::StabilityStatus::Solved;
  json j;
  j["file"] = a.file;
  j["verdict"] = a.verdict == Verdict::Stable             ? "stable"
                 : a.verdict == Verdict::Unstable         ? "unstable"
                 : a.verdict == Verdict::Undecided        ? "undecided"
                 : a.verdict == Verdict::NothingToAnalyse ? "nothing-to-analyse"
                                                          : "unreadable";
  j["stable"] = a.stable();
  if (a.verdict == Verdict::Unreadable) {
    j["error"] = a.fatal;
    return j;
  }
  j["title"] = a.model.title;
  j["main_model"] = a.model.main_block;
  j["parts"] = a.model.parts.size();
  j["bricks"] = a.conversion.assembly.bricks.size();
  j["skipped"] = json::array();
  for (const auto& s : a.conversion.skipped) {
    const auto& p = a.model.parts[s.part];
    j["skipped"].push_back(
        {{"file", p.file}, {"line", p.line}, {"part", p.part}, {"reason", s.reason}});
  }
  j["learnt_parts"] = json::array();
  for (const auto& t : a.conversion.learnt->types())
    j["learnt_parts"].push_back({{"part", t.part},
                                 {"name", t.name},
                                 {"kind", t.kind},
                                 {"length", t.length},
                                 {"width", t.width},
                                 {"height", t.height},
                                 {"mass_g", t.mass_g},
                                 {"mass_source", t.mass_source}});
  j["diagnostics"] = json::array();
  for (const auto& d : a.model.diagnostics)
    j["diagnostics"].push_back(
        {{"severity", d.severity == ldraw::Severity::Error ? "error" : "warning"},
         {"file", d.file},
         {"line", d.line},
         {"message", d.message}});
  j["ground"] = options.stability.ground == physics::GroundMode::Table ? "table" : "baseplate";
  j["components"] = r.connectivity.component_count;
  j["touches_ground"] = !r.connectivity.grounded.empty() &&
                        std::find(r.connectivity.grounded.begin(), r.connectivity.grounded.end(),
                                  1) != r.connectivity.grounded.end();
  j["floating"] = json::array();
  for (int b : r.connectivity.floating) j["floating"].push_back(brick_json(a, b));
  j["status"] = physics::to_string(r.status);
  j["min_cm_gf"] = options.min_cm_gf;
  j["cm_newton"] = number_or_null(solved, r.cm_newton());
  j["cm_gf"] = number_or_null(solved, r.cm_gf());
  j["weakest"] = json::array();
  for (const auto& w : r.weakest)
    j["weakest"].push_back(
        {{"a", brick_json(a, w.lower)}, {"b", brick_json(a, w.upper)}, {"dual", w.share}});
  if (options.steps) {
    j["steps"] = json::array();
    for (const auto& s : a.steps)
      j["steps"].push_back(
          {{"step", s.step},
           {"bricks", s.bricks},
           {"stable", s.stable},
           {"status", physics::to_string(s.status)},
           {"cm_gf", number_or_null(s.status == physics::StabilityStatus::Solved, s.cm_gf)}});
    j["first_failing_step"] = a.first_failing_step ? json(*a.first_failing_step) : json(nullptr);
  }
  j["lp"] = {{"rows", r.stats.rows}, {"columns", r.stats.columns}, {"nonzeros", r.stats.nonzeros}};
  j["timing"] = {{"parse", a.parse_seconds},
                 {"graph", r.stats.graph_seconds},
                 {"build", r.stats.build_seconds},
                 {"solve", r.stats.solve_seconds}};
  return j;
}

}  // namespace lego::report
