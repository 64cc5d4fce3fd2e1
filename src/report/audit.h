#pragma once
// The audit of one LDraw model: its parts, what each became (analysed, carried, left out),
// connectivity, stability and, on request, every build step. brickcheck prints it; legolize
// checks its own output with it.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ldraw/reader.h"
#include "parts/assembly_builder.h"
#include "parts/part_library.h"
#include "physics/stability.h"
#include "report/assumptions.h"

namespace lego::report {

// A type-1 line a builder points at: "LINE" in the model's own file, or "FILE:LINE".
struct LineSpec {
  std::string file;  // "" = the model's own file
  int line = 0;
  // Whether `part`, placed in the model read from `model_file`, is the one named.
  bool names(const ldraw::PlacedPart& part, const std::string& model_file) const;
};

// An external weight (paper section 7) named the way a builder points at a model.
struct LoadSpec {
  enum class Target { Line, Step, Submodel, Top } target = Target::Line;
  LineSpec line;     // Line
  int number = 0;    // Step: step number
  std::string name;  // Submodel: its name
  double grams = 0;
  std::string text;  // as given, for messages
};
// Parses "LINE=GRAMS", "FILE:LINE=GRAMS", "step:K=GRAMS", "submodel:NAME=GRAMS" or "top=GRAMS"
// (the parts whose tops are highest, as legolize --load-top puts it).
// Throws InputError on anything else (a number out of range, a weight that is not finite).
LoadSpec parse_load_spec(const std::string& text);
// Parses "LINE" or "FILE:LINE" (--ground-part). Throws InputError on anything else.
LineSpec parse_line_spec(const std::string& text, const std::string& option);

struct AuditOptions {
  ldraw::ReadOptions read;
  physics::StabilityOptions stability;
  std::vector<LoadSpec> loads;
  std::vector<LineSpec> ground_parts;  // parts the user fixes (--ground-part)
  double min_cm_gf = 0;                // the stability threshold
  bool steps = false;                  // check the assembly after every build step
  bool brick_capacity = false;         // for heat maps
  // A stable verdict that rests on an assumption that can change it is not enough
  // (Verdict::StableByAssumption); the joints are checked with a second analysis without them.
  bool strict = false;
  // Told how far a stage is, for a person watching (Budget); from any thread.
  Budget::Progress progress;
};

struct StepAudit {
  int step = 0;
  int bricks = 0;
  physics::StabilityStatus status = physics::StabilityStatus::Empty;
  double cm_gf = 0;
  int floating = 0;  // bricks and carried parts that reach no ground after this step
  // Parts it builds apart (ldraw::Step::aside): the model in place is as after the step before.
  int aside = 0;
  // It builds a sub-assembly (a submodel with steps of its own), judged alone on the table: what
  // `bricks` and the C_M are of.
  bool apart = false;
  // It builds a sub-assembly aside in MLCad's buffers (ldraw::Step::aside_shown), judged alone on
  // the table as its view shows it: `bricks`, the C_M and the culprits are Audit::aside's.
  bool built_aside = false;
  bool stable = false;
  // cm_gf is a certified lower bound (physics/step_stability.h), not the exact C_M: the exact
  // one is asked of the weakest step alone.
  bool certified = false;
  // When it does not stand: why, naming the parts (file:line) that float, tip or hold least.
  std::string why;
  std::vector<int> culprits;          // bricks of the whole model (AssemblyConversion::assembly)
  std::vector<int> carried_culprits;  // its carried parts (Assembly::carried)
};

enum class Verdict {
  Stable,            // everything analysed connected, grounded, C_M above the threshold
  Unstable,          // C_M at or below the threshold, floating parts, or no equilibrium
  Undecided,         // the solver gave up (iteration limit, numerical trouble)
  NothingToAnalyse,  // parts, but none analysed as structure (all carried or unknown)
  NotJudged,         // stable as analysed, but most of the mass is carried (kMostOfTheMass)
  // With AuditOptions::strict: stable as analysed, but resting on an assumption that can change
  // the verdict (Assumptions::deciding).
  StableByAssumption,
  Unreadable,  // the file could not be read or is not an analysable LDraw model
};

struct Audit {
  std::string file;
  ldraw::Model model;
  parts::AssemblyConversion conversion;
  physics::StabilityResult stability;
  std::vector<StepAudit> steps;
  std::optional<int> first_failing_step;
  // With --steps: the first step left unchecked when --max-seconds ran out (the steps share it).
  std::optional<int> unchecked_from_step;
  std::vector<std::string> load_notes;  // where each load went
  Verdict verdict = Verdict::Unreadable;
  Assumptions assumptions;  // what the verdict rests on
  std::string fatal;        // why the file is unreadable
  // Where --max-seconds ran out (OutOfTime's words), the verdict then Undecided: nothing else
  // of the audit is complete.
  std::string out_of_time;
  // Where the memory budget refused the model or an allocation failed (OutOfMemory's words), the
  // verdict then Undecided: nothing else of the audit is complete.
  std::string out_of_memory;
  double parse_seconds = 0, parts_seconds = 0;
  // 2 when a first analysis named parts resting where they cannot stay and they were carried:
  // the stats' times are then those of both.
  int analyses = 0;

  // With steps: the parts built aside in MLCad's buffers (ldraw::Model::aside), converted as a
  // model of their own on the table, for the steps that build them.
  std::unique_ptr<Audit> aside;

  bool stable() const { return verdict == Verdict::Stable; }
};

// `library` caches part knowledge across the files of a run.
Audit audit_file(const std::filesystem::path& path, const AuditOptions& options,
                 parts::PartLibrary& library);

// The model's part that analysed brick `brick` is (Audit::conversion.brick_part).
const ldraw::PlacedPart& placed_part(const Audit& audit, int brick);
// "tower.ldr:12 3001 Red at (0, -24, 0)": how reports name a brick, with its LDraw position.
std::string describe_brick(const Audit& audit, int brick);
// The same for a carried part (an index into Assembly::carried).
std::string describe_carried(const Audit& audit, int carried);
// How many bricks lie on a lattice of their own (Brick::frame), as reports count them.
int turned_lattice_bricks(const Assembly& assembly);

}  // namespace lego::report
