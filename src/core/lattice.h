#pragma once
#include <cmath>

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

// Where a coordinate lies on a grid of `pitch` (LDU): its residue in hundredths of an LDU, in
// [0, pitch·100), what the parts of a model vote on to find the grid they share (the plates'
// height, the studs across).
inline long residue_hundredths(double v, double pitch) {
  return std::lround(std::fmod(std::fmod(v, pitch) + pitch, pitch) * 100) %
         std::lround(pitch * 100);
}
// The shift in [−pitch/2, pitch/2] that brings v onto the nearest line of the grid of `pitch`
// through `at`: how far an editor's nudge moved it.
inline double onto_grid(double v, double at, double pitch) {
  double d = std::fmod(v - at, pitch);
  if (d > pitch / 2) d -= pitch;
  if (d < -pitch / 2) d += pitch;
  return -d;
}

// A stud is 6 LDU in radius and its receptacle's cell reaches 10 LDU either side of the
// receptacle: a stud whose centre a model draws within this of a receptacle's, on a part touching
// the receptacle's part face to face, lies inside that cell and can be nowhere but in the
// receptacle. How far a part placed by eye may be from where it snaps.
inline constexpr double kStudInCellLdu = kLduPerStud / 2.0 - 6.0;

struct LatticePoint {
  int x = 0, y = 0, z = 0;
  friend bool operator==(const LatticePoint&, const LatticePoint&) = default;
};

}  // namespace lego
