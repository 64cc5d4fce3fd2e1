#pragma once
// What a verdict rests on (docs/physics.md, "What a verdict assumes"): how much of the model is
// analysed and how much carried, by count and by mass; the assumed-rigid joints; and which of
// the assumptions can change the verdict, the ones brickcheck --strict fails on.
#include <string>
#include <vector>

namespace lego::report {

struct Audit;

// A model with more than this share of its mass carried gets no verdict (Verdict::NotJudged):
// what is analysed says little of what stands.
inline constexpr double kMostOfTheMass = 0.5;

struct Assumption {
  enum class Kind {
    // Carried parts tie analysed parts together rigidly, or parts of two lattices touch: it can
    // change the verdict where the model is not stable without such joints.
    Joint,
    // A carried part that does not rest on what is under it hangs on one analysed part by a
    // connection that is not modelled (a wing on a clip, a flag in a hole): it can fall.
    Held,
    // A part left out, its file not found: its weight and its connections are unknown.
    Unknown,
  };
  Kind kind = Kind::Held;
  std::string text;  // one line, parts named by file:line
};

struct Assumptions {
  int analysed = 0, carried = 0, left_out = 0;     // occurrences; left out without the copies
  int parts = 0;                                   // placed, copies included
  double analysed_mass_g = 0, carried_mass_g = 0;  // without the ground's own parts
  int rigid_joints = 0;
  // The assumptions that can change the verdict: held and unknown parts always; the joints when
  // the model, analysed without them, is not stable (`joints_checked`).
  std::vector<Assumption> deciding;
  bool joints_checked = false;
  std::string without_joints;  // what the model is without them, when checked

  double carried_share() const {
    const double all = analysed_mass_g + carried_mass_g;
    return all > 0 ? carried_mass_g / all : 0;
  }
  // "12 rigid joints; 30 of 48 parts carried (41% of the mass); 2 left out", or "" when the
  // verdict assumes nothing.
  std::string summary() const;
};

// What the audit's analysis assumes; the joints are not checked here (audit.cpp does that for
// --strict, with a second analysis).
Assumptions assumptions_of(const Audit& audit);
// Each assumed-rigid joint of the audit's analysis as an assumption that can change the verdict.
std::vector<Assumption> joint_assumptions(const Audit& audit);

}  // namespace lego::report
