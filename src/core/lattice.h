#pragma once
// The LEGO lattice and its units. Lattice coordinates: x and z in studs, y in plates counted
// upwards. LDraw coordinates (LDU, -y up) are converted in src/ldraw/ only.

namespace lego {

inline constexpr int kLduPerStud = 20;
inline constexpr int kLduPerPlate = 8;
inline constexpr int kPlatesPerBrick = 3;

// Physical lengths, used where torques need real proportions.
inline constexpr double kMmPerStud = 8.0;
inline constexpr double kMmPerPlate = 3.2;

// A plate's height expressed in studs (8 LDU / 20 LDU): the vertical unit of physics code.
inline constexpr double kStudsPerPlate = double(kLduPerPlate) / double(kLduPerStud);

struct LatticePoint {
  int x = 0, y = 0, z = 0;
  friend bool operator==(const LatticePoint&, const LatticePoint&) = default;
};

}  // namespace lego
