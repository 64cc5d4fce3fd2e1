#pragma once
// Parts drawn by eye: LDraw editors nudge parts by one LDU, and authors place parts where they
// look right rather than where the lattice is. This stage of the audit owns every move of a part
// onto the lattice, each with a warning naming its line; the builder places parts as drawn and
// the contact graph's tolerances (a stud ring's common shift, a wheel's reach onto its pin) move
// nothing.
#include <functional>
#include <vector>

#include "parts/assembly_builder.h"

namespace lego::report {

// The editor's nudge: an upright brick with studs or receptacles, on the model's lattice, drawn
// within one LDU above or below the plates the rest of the model shares (conversion.plates) is
// taken as on them. Two LDU is a placement of its own, and across, a part one LDU off may be a
// SNOT assembly offset as a whole on purpose (the town hall's): both stay as drawn.
void take_onto_the_plates(parts::AssemblyConversion& conversion);

// The bricks that reach no ground, per brick (PHYSICS.md "Floating").
using FloatingBricks = std::function<std::vector<char>(const Assembly&)>;

// Placed by eye: bricks whose studs and receptacles meet nothing that stands (`floating`) are
// moved onto the lattice most bricks share, and those that then meet what stands stay moved.
// Returns whether any did.
bool nudge_onto_the_lattice(parts::AssemblyConversion& conversion,
                            const std::vector<char>& floating, const FloatingBricks& floating_now);

}  // namespace lego::report
