#pragma once
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "report/audit.h"

namespace lego::report {

// What a builder reads: parts, connectivity, stability, steps, timing. `quiet` keeps only the
// verdict line and errors.
std::string render_text(const Audit& audit, bool quiet);

// The object documented in docs/brickcheck-json.md.
nlohmann::json render_json(const Audit& audit, const AuditOptions& options);

// The model re-coloured by per-brick capacity (red, orange, yellow, green), with `0 //` comments
// naming the weakest contacts. Needs Audit::stability.brick_capacity.
std::string render_heatmap(const Audit& audit);
// The same for any assembly and its analysis; `describe` names a brick index (or kGround).
std::string render_heatmap(const Assembly& assembly, const physics::StabilityResult& stability,
                           const std::string& title, const std::string& author,
                           const std::function<std::string(int)>& describe);

// The LDraw colour code a heat map gives a brick of this capacity (g·m/s²).
int heat_color(double capacity);

}  // namespace lego::report
