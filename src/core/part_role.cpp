#include "core/part_role.h"

namespace lego {

std::string_view carried_because(PartRole r) {
  switch (r) {
    case PartRole::DrawsNoBody:
      return "its file draws no body";
    case PartRole::MinifigurePart:
      return "a minifigure part (its joints are not modelled)";
    case PartRole::HingeWithoutCells:
      return "a hinge half without cells of its own (it turns)";
    case PartRole::Turntable:
      return "a turntable (it turns)";
    case PartRole::Door:
      return "a door (it hangs on hinge pins)";
    case PartRole::WheelWithoutAxleLine:
      return "a wheel or tyre whose axle line its file does not draw";
    case PartRole::NoConnections:
      return "no studs, receptacles, pin holes, pins, axles, bars or clips (its connections are "
             "not modelled)";
    case PartRole::ScaledOrSheared:
      return "its matrix is scaled or sheared";
    case PartRole::TurnedOffQuarter:
      return "turned by an angle that is not a multiple of 90 degrees";
    case PartRole::BarUnclipped:
      return "a bar no clip holds (what holds it is not modelled)";
    case PartRole::WheelOnNothing:
      return "a wheel or tyre on no pin or axle we find (what holds it is not modelled)";
    case PartRole::ShaftsMeetNothing:
      return "its pins, axles, holes, bars and clips meet nothing that stands";
    case PartRole::TurnsOnItsHalf:
      return "a hinge or turntable half: it turns on what holds it";
    case PartRole::MeetsNothing:
      return "its studs and receptacles meet nothing that stands";
    case PartRole::RestsOutOfPlace:
      return "it rests where it cannot stay, snapped to nothing that stands";
    case PartRole::OnTiltedLattice:
      return "on a lattice tilted off the vertical, where nothing holds it against the twist "
             "about its studs";
    case PartRole::UnknownPart:
      return "nothing is known of the part";
    case PartRole::MissingSubmodel:
      return "a submodel no file holds";
    case PartRole::Copy:
      return "a copy of another part in the same place";
  }
  return "";
}

}  // namespace lego
