#pragma once
// The audit of one LDraw model: its parts, the bricks they became, connectivity, stability and,
// on request, every build step. brickcheck prints it; legolize checks its own output with it.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ldraw/assembly_builder.h"
#include "ldraw/reader.h"
#include "physics/stability.h"

namespace lego::report {

// An external weight (paper section 7) named the way a builder points at a model.
struct LoadSpec {
  enum class Target { Line, Step, Submodel } target = Target::Line;
  std::string file;  // Line: the file holding the line ("" = the model's own file)
  int number = 0;    // Line: line number; Step: step number
  std::string name;  // Submodel: its name
  double grams = 0;
  std::string text;  // as given, for messages
};
// Parses "LINE=GRAMS", "FILE:LINE=GRAMS", "step:K=GRAMS" or "submodel:NAME=GRAMS".
// Throws InputError on anything else.
LoadSpec parse_load_spec(const std::string& text);

struct AuditOptions {
  ldraw::ReadOptions read;
  physics::StabilityOptions stability;
  std::vector<LoadSpec> loads;
  double min_cm_gf = 0;         // the stability threshold
  bool steps = false;           // check the assembly after every build step
  bool brick_capacity = false;  // for heat maps
};

struct StepAudit {
  int step = 0;
  int bricks = 0;
  physics::StabilityStatus status = physics::StabilityStatus::Empty;
  double cm_gf = 0;
  bool stable = false;
};

enum class Verdict {
  Stable,            // every analysed brick connected, grounded, C_M above the threshold
  Unstable,          // C_M at or below the threshold, floating bricks, or no equilibrium
  Undecided,         // the solver gave up (iteration limit, numerical trouble)
  NothingToAnalyse,  // parts, but none became a brick
  Unreadable,        // the file could not be read or is not an analysable LDraw model
};

struct Audit {
  std::string file;
  ldraw::Model model;
  ldraw::AssemblyConversion conversion;
  physics::StabilityResult stability;
  std::vector<StepAudit> steps;
  std::optional<int> first_failing_step;
  std::vector<std::string> load_notes;  // where each load went
  Verdict verdict = Verdict::Unreadable;
  std::string fatal;  // why the file is unreadable
  double parse_seconds = 0;

  bool stable() const { return verdict == Verdict::Stable; }
};

Audit audit_file(const std::filesystem::path& path, const AuditOptions& options);

// "3001 Red at (0, -24, 0)" — how reports name a brick, with its LDraw position.
std::string describe_brick(const Audit& audit, int brick);

}  // namespace lego::report
