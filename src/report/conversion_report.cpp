#include "report/conversion_report.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace lego::report {

namespace {
nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
}  // namespace

std::string NamedBrick::words() const {
  return fmt::format("{} ({}) {}", name, part, where);
}

nlohmann::json to_json(const ConversionReport& r) {
  nlohmann::json j;
  j["input"] = r.input;
  j["output"] = r.output;
  j["up"] = r.up;
  j["warnings"] = r.warnings;
  j["voxels"] = r.voxels;
  j["inside_voxels_coloured"] = r.inside_voxels_coloured;
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
  j["decided"] = r.decided;
  j["solver_final"] =
      r.solver_final.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.solver_final);
  j["solver_note_final"] =
      r.solver_note_final.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.solver_note_final);
  j["stable"] = r.stable;
  j["iterations"] = r.iterations;
  j["accepted"] = r.accepted;
  j["lp_solves"] = r.lp_solves;
  j["refine_out_of_time"] = r.refine_out_of_time;
  j["rejected_by_bound"] = r.rejected_by_bound;
  nlohmann::json seconds = nlohmann::json::object();
  for (auto& [stage, s] : r.seconds) seconds[stage] = s;
  j["seconds"] = seconds;
  if (!r.bottleneck.empty()) j["bottleneck"] = r.bottleneck;
  if (!r.bottleneck_bricks.empty()) {
    nlohmann::json named = nlohmann::json::array();
    for (const NamedBrick& b : r.bottleneck_bricks)
      named.push_back({{"part", b.part},
                       {"name", b.name},
                       {"step", b.step},
                       {"where", b.where},
                       {"voxel", b.voxel}});
    j["bottleneck_bricks"] = named;
  }
  nlohmann::json steps = nlohmann::json::array();
  double smallest = std::numeric_limits<double>::infinity();
  for (const StepReport& s : r.steps) {
    nlohmann::json step = {{"step", s.step},
                           {"new_bricks", s.new_bricks},
                           {"bricks", s.bricks},
                           {"cm_gf", s.analysed ? number_or_null(s.cm_gf) : nullptr},
                           {"stands", s.analysed ? nlohmann::json(s.stands) : nullptr},
                           {"certified", s.certified},
                           {"supports", s.supports}};
    if (!s.why.empty()) step["why"] = s.why;
    steps.push_back(step);
    if (s.analysed) smallest = std::min(smallest, s.cm_gf);
  }
  j["steps"] = steps;
  j["steps_stand"] = r.steps_analysed ? nlohmann::json(r.steps_stand) : nullptr;
  j["min_step_cm_gf"] =
      r.steps.empty() || !r.steps_analysed ? nlohmann::json(nullptr) : number_or_null(smallest);
  j["held_back"] = r.held_back;
  nlohmann::json pieces = nlohmann::json::array();
  for (const PieceReport& p : r.pieces)
    pieces.push_back(
        {{"piece", p.piece},
         {"grounded", p.grounded},
         {"lift_layers", p.lift},
         {"objects", p.objects},
         {"voxels", p.voxels},
         {"bricks", p.bricks},
         {"components", p.components},
         {"components_before_joining", p.components_before_joining},
         {"voxels_added", p.voxels_added},
         {"supports",
          {{"columns", p.support_columns},
           {"bricks", p.support_bricks},
           {"voxels", p.support_voxels}}},
         {"inside_columns", {{"columns", p.inside_columns}, {"voxels", p.inside_column_voxels}}},
         {"cm_gf", number_or_null(p.cm_gf)},
         {"stable", p.stable},
         {"steps_stand", p.steps_stand},
         {"submodel", p.submodel.empty() ? nlohmann::json(nullptr) : nlohmann::json(p.submodel)}});
  j["pieces"] = pieces;
  j["pieces_before_joining"] = r.pieces_before_joining;
  j["voxels_added_to_join"] = r.voxels_added_to_join;
  j["colour_changes"] = {{"visible_voxels", r.colour_changes.visible},
                         {"changed", r.colour_changes.changed},
                         {"mean_distance", r.colour_changes.mean_distance},
                         {"max_distance", r.colour_changes.max_distance}};
  j["inside_columns"] = {{"columns", r.inside_columns}, {"voxels", r.inside_column_voxels}};
  j["supports"] = {{"columns", r.support_columns},
                   {"bricks", r.support_bricks},
                   {"color", r.support_bricks > 0 ? nlohmann::json(r.support_color) : nullptr}};
  j["floating_objects"] = {{"objects", r.floating.objects},
                           {"columns", r.floating.columns},
                           {"voxels", r.floating.voxels},
                           {"still_floating", r.floating.still_floating}};
  j["seed"] = r.seed;
  j["version"] = r.version;
  return j;
}

}  // namespace lego::report
