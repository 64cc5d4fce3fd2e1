#pragma once
// What a placed part is to the analysis when it is not a brick of the structure, and why: carried
// (PHYSICS.md "Carried parts": its weight kept, its connections not modelled) or left out (nothing
// is known of it). One value per rule that decides it; the words the reports give are here only.
#include <cstdint>
#include <string_view>

namespace lego {

enum class PartRole : uint8_t {
  // Carried for what the part is (parts/derive.cpp).
  DrawsNoBody,
  MinifigurePart,
  HingeWithoutCells,
  Turntable,
  Door,
  WheelWithoutAxleLine,
  NoConnections,
  // Carried for how it is placed (parts/assembly_builder.cpp).
  ScaledOrSheared,
  TurnedOffQuarter,
  // Carried for what the audit finds around it (report/audit.cpp).
  BarUnclipped,
  WheelOnNothing,
  ShaftsMeetNothing,
  TurnsOnItsHalf,
  MeetsNothing,
  RestsOutOfPlace,
  OnTiltedLattice,
  // Left out (parts/assembly_builder.cpp).
  UnknownPart,
  MissingSubmodel,
  Copy,
};

// Why a carried part is carried, as the reports say it. Left-out parts' words name files
// (parts::PartNote::reason).
std::string_view carried_because(PartRole r);

}  // namespace lego
