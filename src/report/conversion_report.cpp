#include "report/conversion_report.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lego::report {

namespace {
nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
}  // namespace

nlohmann::json to_json(const ConversionReport& r) {
  nlohmann::json j;
  j["input"] = r.input;
  j["output"] = r.output;
  j["voxels"] = r.voxels;
  j["voxels_filled"] = r.voxels_filled;
  j["bricks"] = r.bricks;
  j["bricks_by_part"] = r.bricks_by_part;
  j["components"] = r.components;
  j["single_connected"] = r.single_connected;
  j["min_cm_gf"] = r.min_cm_gf;
  j["cm_gf_initial"] = number_or_null(r.cm_gf_initial);
  j["cm_gf_final"] = number_or_null(r.cm_gf_final);
  j["status_initial"] = r.status_initial;
  j["status_final"] = r.status_final;
  j["stable"] = r.stable;
  j["iterations"] = r.iterations;
  j["accepted"] = r.accepted;
  j["lp_solves"] = r.lp_solves;
  j["rejected_by_bound"] = r.rejected_by_bound;
  nlohmann::json seconds = nlohmann::json::object();
  for (auto& [stage, s] : r.seconds) seconds[stage] = s;
  j["seconds"] = seconds;
  if (!r.bottleneck.empty()) j["bottleneck"] = r.bottleneck;
  nlohmann::json steps = nlohmann::json::array();
  double smallest = std::numeric_limits<double>::infinity();
  for (const StepReport& s : r.steps) {
    nlohmann::json step = {{"step", s.step},
                           {"new_bricks", s.new_bricks},
                           {"bricks", s.bricks},
                           {"cm_gf", s.analysed ? number_or_null(s.cm_gf) : nullptr},
                           {"stands", s.analysed ? nlohmann::json(s.stands) : nullptr}};
    if (!s.why.empty()) step["why"] = s.why;
    steps.push_back(step);
    if (s.analysed) smallest = std::min(smallest, s.cm_gf);
  }
  j["steps"] = steps;
  j["steps_stand"] = r.steps_analysed ? nlohmann::json(r.steps_stand) : nullptr;
  j["min_step_cm_gf"] =
      r.steps.empty() || !r.steps_analysed ? nlohmann::json(nullptr) : number_or_null(smallest);
  j["held_back"] = r.held_back;
  j["seed"] = r.seed;
  j["version"] = r.version;
  return j;
}

}  // namespace lego::report
