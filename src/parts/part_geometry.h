#pragma once
// A part file flattened into what its primitives say: the faces of its body (studs left out) and
// its studs, in the part's own frame. Each file is flattened once and reused wherever it is
// placed; the expansion is bounded (kMaxFaces), so parts that fan out cannot run away.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/part_shape.h"
#include "parts/part_files.h"

namespace lego::parts {

inline constexpr size_t kMaxFaces = 2'000'000;
// Studs a part may have (straight and angled): a 48 x 48 baseplate has 2,304.
inline constexpr size_t kMaxStuds = 100'000;

struct Triangle {
  std::array<Vec3, 3> p;
};

// A cylinder primitive's surface along one of the part's axes: from `a` to `b`, its radius, the
// share of a full turn it draws (2-4cyli.dat: 0.5), and whether a clip primitive (clip*.dat)
// draws it.
struct Round {
  Vec3 a{0, 0, 0}, b{0, 0, 0};
  double radius = 0, turn = 1;
  bool clip = false;
};

struct PartGeometry {
  std::vector<Triangle> faces;   // type 3 and 4 lines, stud primitives left out
  std::vector<Connector> studs;  // stud primitives whose axis is one of the six directions
  int angled_studs = 0;          // stud primitives at other angles
  // Technic hole, pin and axle primitives along one of the axes, each as drawn (a pin hole's end
  // rings, a pin's halves: derive.cpp joins them); those at other angles are left out.
  std::vector<Shaft> shafts;
  // Cylinder primitives (…cyli, …cylo, …cylc) at least 2 LDU in radius along one of the axes:
  // where a hinge half may turn, a bar, a clip's grip (derive.cpp tells which). Those inside stud
  // and tube primitives are left out.
  std::vector<Round> rounds;
  std::string title;                 // the file's first line, "~Moved to" followed
  std::string category;              // !CATEGORY, or the title's first word
  std::vector<std::string> missing;  // subfiles not found, each name once, sorted
};

// Finds the file behind a reference made inside a part; nullopt with `why` when there is none.
using FileFinder =
    std::function<std::optional<PartFile>(std::string_view reference, std::string& why)>;

// Flattens part files through `find`, remembering every file flattened (by PartFile::key).
class GeometryCache {
 public:
  // The geometry of the file, or nullptr with `why` (nested too deeply, a reference loop, more
  // than kMaxFaces faces or kMaxStuds studs). A failure is remembered too (but for the nesting
  // limit, which depends on the way in): a part placing the failing file 20 times fails once.
  std::shared_ptr<const PartGeometry> flatten(const PartFile& file, const FileFinder& find,
                                              std::string& why);

 private:
  std::unordered_map<std::string, std::shared_ptr<const PartGeometry>> done_;
  std::unordered_map<std::string, std::string> failed_;  // file key -> why
  bool depth_failure_ = false;  // the failure on its way up is the nesting limit
  std::vector<std::string> stack_;
};

// A part may be at most this many LDU across (1,000 studs); part_library.cpp leaves out larger.
inline constexpr double kMaxPartExtentLdu = 20'000;
// The largest extent of the geometry's faces and studs along x, y or z, in LDU (0 when empty).
double geometry_extent(const PartGeometry& geometry);

// Whether a primitive's file name (no folder) is a stud: stud.dat, stud2.dat, stud10.dat ...
// but not the underside tubes and pins (stud3*, stud4*, stud12, stud16, stud18*, stud2s*).
bool is_stud_primitive(std::string_view base_name);

// The Technic connection a primitive draws along its y axis, by its file name (no folder): pin
// holes (peghole*, npeghol*, connhol*, beamhol*), axle holes (axlehole, axlehol*, axl2hol*,
// axl3hol*, axl5hol*), pins (connect*, wpin*), friction pins (confric*) and axles (axle.dat);
// nullopt for any
// other file (the bushes, bush*.dat, do not lie along their y axis).
std::optional<Shaft::Kind> shaft_primitive(std::string_view base_name);

}  // namespace lego::parts
