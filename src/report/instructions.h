#pragma once
// Building instructions a person can follow: an HTML booklet with a cover (the finished model and
// every part) and a page per build step (the model so far with the new parts highlighted, the
// parts the step needs drawn one by one and listed, and the step's C_M), and its printable PDF.
// Pictures come from LeoCAD (DESIGN.md, "Real clients"), the PDF from headless Chromium; without
// them the booklet is written without pictures or PDF and says so.
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/part_shape.h"
#include "ldraw/reader.h"
#include "report/parts_list.h"

namespace lego::report {

struct BookletStep {
  int number = 0;                // LDraw step of the main model, from 1
  std::vector<PartCount> parts;  // placed in this step
  // The model after this step, as brickcheck --steps analyses it; empty when not analysed.
  std::optional<double> cm_gf;  // no value also when the step has no number (no equilibrium)
  std::optional<bool> stands;
  bool certified = false;  // cm_gf is a certified lower bound, not the exact C_M
  bool floats = false;     // some of it reaches no ground: cm_gf is only that of what stands
  std::string why;         // when it does not stand
  std::string note;        // a word for the builder on this step (legolize: the supports)
  bool aside = false;      // it builds a sub-assembly apart (ldraw::Step::aside), not the model
  bool sub_assembly_judged = false;  // cm_gf and stands are the sub-assembly's, on the table
  // When it does not stand: the parts (indices into the model's parts) that float, tip or hold
  // least, drawn apart in a picture of what falls (draw_what_falls).
  std::vector<size_t> falling;
};

struct Booklet {
  std::string title;
  std::string source;  // the model file, as shown
  std::vector<BookletStep> steps;
  std::vector<PartCount> parts;  // every part of the model
  std::optional<double> cm_gf;   // of the finished model
  std::string verdict;           // one line on the finished model
  ldraw::ColorTable colors;      // names and looks of the colours (the model's table)
  // What the pictures show: every part where the model puts it, as one LDraw file with a STEP
  // after each of `steps`, so that a renderer's step k is steps[k - 1], and LeoCAD's camera
  // kStepCamera framing each step (step_camera.h).
  std::string drawn;
  // The parts the model embeds (a packed MPD's), as FILE blocks a renderer reads after `drawn`.
  std::string embedded;
  // What falls (draw_what_falls): an LDraw file with a STEP per step of `falls_steps` (their
  // numbers) that names falling parts, drawing them in red and the model so far in clear, framed
  // by LeoCAD's camera kStepCamera on them.
  std::string falls;
  std::vector<int> falls_steps;
};

// The parts of a model read from LDraw, step by step (submodels flattened; a sub-assembly's
// parts listed in the steps that build it apart, ldraw::Step). Names come from the catalog or the
// part's own file.
// `bodies`, when given, is per part of the model its body in its own frame where known: the
// pictures frame each step on it (step_camera.h).
Booklet booklet_of(const ldraw::Model& model, const std::vector<std::optional<Box>>& bodies = {});

// The pictures of what falls: for each step whose `falling` parts are known (the first 20), the
// model as that step leaves it (or the sub-assembly, for a step judged on the table) in clear and
// those parts in red, seen through it where they are inside. Call once the steps' analyses are
// filled in.
void draw_what_falls(Booklet& booklet, const ldraw::Model& model,
                     const std::vector<std::optional<Box>>& bodies = {});

// Progress on the way (stderr lines for a person watching).
using BookletProgress = std::function<void(const std::string&)>;

// Throws InputError unless a booklet may be written into DIR (see write_booklet); creates nothing.
void check_booklet_folder(const std::filesystem::path& dir);

// Writes DIR/index.html and its pictures (DIR/step-NNN.png, DIR/cover.png, DIR/part-NNN.png),
// rendering the booklet's own file with LeoCAD and the parts library `library`. DIR may
// not exist, be empty, or hold a booklet written before (which is replaced); anything else is
// refused with InputError, so nothing a user keeps there is overwritten. Returns a note on the
// pictures (empty when all were rendered).
std::string write_booklet(const std::filesystem::path& dir, const Booklet& booklet,
                          const std::filesystem::path& library,
                          const BookletProgress& progress = {});

}  // namespace lego::report
