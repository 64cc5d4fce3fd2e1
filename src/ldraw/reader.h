#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/budget.h"
#include "ldraw/color_table.h"
#include "ldraw/transform.h"

namespace lego::ldraw {

enum class Severity { Warning, Error };

struct Diagnostic {
  Severity severity = Severity::Warning;
  std::string file;
  int line = 0;
  std::string message;
  std::string text() const;  // "file:line: error: message"
};

// A submodel reference as it was expanded: the placement holding it (an index into
// Model::placements, -1 for the main model) and its line's transform. Each expansion is one, so
// two placements of one submodel differ.
struct SubmodelPlacement {
  int parent = -1;
  Transform transform;
};

// A part placed in the world after flattening submodels.
struct PlacedPart {
  std::string part;       // normalized reference: "3001", "s/3068bs01"
  std::string reference;  // as written on the type-1 line
  int color = kMainColor;
  Transform transform;  // world placement
  // How: the innermost submodel placement holding its line (Model::placements, -1 for the main
  // model) and the line's own transform. The placements' product with it is `transform`; each is
  // exactly as written, so what lies on a lattice inside a submodel placed at an angle stays
  // exactly on it there.
  int inside = -1;
  Transform local;
  std::string file;  // where the type-1 line that placed it is
  int line = 0;
  int step = 1;                      // step of the main model (1-based) at which it appears
  std::string submodel;              // the model block holding the line ("" = main model)
  std::filesystem::path definition;  // its part file, when one was found on disk
  std::string embedded_definition;   // its FILE block name, when the MPD embeds it
  // Placed by a `0 GHOST` line (MLCad): part of the model as drawn, not of its parts list (it
  // shows in place a sub-assembly built aside, whose own lines are counted).
  bool ghost = false;
  // The step that builds it apart, in a sub-assembly (a submodel with steps of its own, the first
  // time it is placed): it is in place from `step`, which places the sub-assembly whole. 0: it is
  // built in place, at `step`.
  int built_in = 0;
  int apart_from = 0;  // with built_in: the sub-assembly's first step (which one it is part of)
};

// One step of the main model, ended by `0 STEP`, `0 ROTSTEP` or the end of the file; a step that
// places no part is not one (a leading ROTSTEP does not make an empty step 1). A submodel's own
// steps come where it is first placed, before the step that places it (PlacedPart::built_in).
struct Step {
  int number = 1;
  int parts = 0;        // placed parts added in this step (after flattening)
  std::string rotstep;  // the ROTSTEP that ended it, if any ("0 0 180 REL", "END")
  int aside = 0;        // parts built apart in it (PlacedPart::built_in, Model::aside)
  // Where it builds a sub-assembly aside in MLCad's buffers: the parts built aside that its view
  // shows at its end (indices into Model::aside, ascending), the sub-assembly as built so far.
  std::vector<int> aside_shown;
};

struct Model {
  std::string source;                          // the path given, or the name of an in-memory text
  std::string title, name, author, ldraw_org;  // header of the main model
  std::string main_block;                      // name of the main model's FILE block
  std::vector<std::string> submodels;          // model blocks used while flattening (no parts)
  // The model files read: the main one (read_file) and every external submodel file, once each.
  std::vector<std::filesystem::path> files;
  std::vector<PlacedPart> parts;
  // Parts a BUFEXCHG sequence builds aside (a sub-assembly shown alone while it is built) and
  // that are not shown at the model's end: not in the finished model, which has them in place by
  // other lines (GHOST, usually), but in its parts list and in the steps that build them.
  std::vector<PlacedPart> aside;
  std::vector<SubmodelPlacement> placements;  // those that hold a part, directly or not
  std::vector<Step> steps;                    // steps[k].number is k + 1
  std::vector<Color> colors;                  // `0 !COLOUR` definitions found in the file
  // What the colours are called and look like: ours (ldraw_parts/LDConfig.ldr), then the
  // libraries' LDConfig.ldr for codes we lack, then the file's own definitions.
  ColorTable color_table;
  std::vector<Diagnostic> diagnostics;

  bool has_errors() const;
  // Embedded part definitions (packed MPD): name -> lines, for analysing unknown parts.
  std::vector<std::pair<std::string, std::string>> embedded_parts;
};

struct ReadOptions {
  std::vector<std::filesystem::path> library_dirs;  // LDraw libraries: parts/, p/, models/
  std::optional<std::string> main_model;            // choose an MPD's main model by name
  std::size_t max_parts = 2'000'000;  // a model expanding to more is refused (exponential nesting)
  int max_depth = 64;
  const Budget* budget = nullptr;  // reading stops with OutOfTime when it is spent
};

// Reads a .ldr/.mpd from disk. Never throws for bad content: problems become diagnostics.
Model read_file(const std::filesystem::path& path, const ReadOptions& options = {});
// Reads LDraw text held in memory; `name` is used in diagnostics and to resolve relative files.
Model read_text(std::string_view text, const std::string& name, const ReadOptions& options = {});

// The LDraw library directories named by $LDRAWDIR, if set.
std::vector<std::filesystem::path> library_dirs_from_env();

}  // namespace lego::ldraw
