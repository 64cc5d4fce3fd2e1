#include "parts/part_geometry.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "core/text.h"
#include "ldraw/tokens.h"
#include "ldraw/transform.h"

namespace lego::parts {
namespace {

using ldraw::next_token;
using ldraw::Transform;
using ldraw::trim;

bool number(std::string_view token, double& v) {
  if (token.starts_with("+")) token.remove_prefix(1);
  auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  return ec == std::errc() && p == token.data() + token.size() && std::isfinite(v);
}

std::string base_name(std::string_view reference) {
  std::string name = safe_reference(reference);
  const auto slash = name.rfind('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

Vec3 transformed(const Transform& t, const Vec3& p) {
  Vec3 out{t.pos[0], t.pos[1], t.pos[2]};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out[r] += t.rot[3 * r + k] * p[k];
  return out;
}

// The direction (core/part_shape.h) that `d` points along, if it lies along one of the axes.
std::optional<int> axis_direction(const Vec3& d) {
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int a = 0; a < 3; ++a)
    if (std::abs(std::abs(d[a]) - length) < 1e-3 * length) return direction_of(a, d[a] < 0);
  return std::nullopt;
}

// The direction a stud placed by `t` points (its primitive points to -y), if axis-aligned.
std::optional<int> stud_direction(const Transform& t) {
  return axis_direction({-t.rot[1], -t.rot[4], -t.rot[7]});
}

// Splits text into lines at LF, CR LF or a bare CR.
template <class F>
void for_each_line(std::string_view text, F&& f) {
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) end = text.size();
    f(text.substr(pos, end - pos));
    pos = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
  }
}

}  // namespace

double geometry_extent(const PartGeometry& g) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  auto take = [&](const Vec3& p) {
    for (size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  };
  for (const Triangle& t : g.faces)
    for (const Vec3& p : t.p) take(p);
  for (const Connector& s : g.studs) take(s.at);
  double extent = 0;
  for (size_t a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
  return extent;
}

bool is_stud_primitive(std::string_view b) {
  if (!b.starts_with("stud") || b.starts_with("stud3") || b.starts_with("stud4") ||
      b.starts_with("stud2s") || b.starts_with("stud12") || b.starts_with("stud16") ||
      b.starts_with("stud18"))
    return false;
  return b.ends_with(".dat");
}

std::optional<Shaft::Kind> shaft_primitive(std::string_view b) {
  if (!b.ends_with(".dat")) return std::nullopt;
  for (const char* hole : {"peghole", "npeghol", "connhol", "beamhol"})
    if (b.starts_with(hole)) return Shaft::Kind::PinHole;
  for (const char* hole : {"axlehol", "axl2hol", "axl3hol", "axl5hol"})
    if (b.starts_with(hole)) return Shaft::Kind::AxleHole;
  if (b.starts_with("confric")) return Shaft::Kind::FrictionPin;
  for (const char* pin : {"connect", "wpin"})
    if (b.starts_with(pin)) return Shaft::Kind::Pin;
  if (b == "axle.dat") return Shaft::Kind::Axle;
  return std::nullopt;
}

namespace {

// The share of a full turn a cylinder primitive draws, by its file name: 2-4cyli.dat 0.5,
// 48/4-4cylo.dat 1; nullopt for any other file.
std::optional<double> cylinder_turn(std::string_view b) {
  if (b.empty() || !std::isdigit(static_cast<unsigned char>(b.front())) || !b.ends_with(".dat"))
    return std::nullopt;
  const auto dash = b.find('-');
  if (dash == std::string_view::npos) return std::nullopt;
  const std::string_view shape = b.substr(dash + 1);
  const auto cyl = shape.find("cyl");
  if (cyl == std::string_view::npos || shape.size() <= cyl + 3 ||
      (shape[cyl + 3] != 'i' && shape[cyl + 3] != 'o' && shape[cyl + 3] != 'c') ||
      shape.substr(cyl + 4) != ".dat")
    return std::nullopt;
  int part = 0, whole = 0;
  const std::string_view n = b.substr(0, dash), d = shape.substr(0, cyl);
  if (std::from_chars(n.data(), n.data() + n.size(), part).ptr != n.data() + n.size() ||
      std::from_chars(d.data(), d.data() + d.size(), whole).ptr != d.data() + d.size() ||
      part <= 0 || whole <= 0)
    return std::nullopt;
  return std::min(1.0, double(part) / whole);
}

// Why `g` with `sub` added would pass kMaxFaces or kMaxStuds, or nullptr.
const char* over_limits(const PartGeometry& g, const PartGeometry& sub) {
  if (g.faces.size() + sub.faces.size() > kMaxFaces) return "it draws more than 2,000,000 faces";
  if (g.studs.size() + size_t(g.angled_studs) + sub.studs.size() + size_t(sub.angled_studs) >
      kMaxStuds)
    return "it has more than 100,000 studs";
  return nullptr;
}

// A stud primitive placed by `t`: a stud where its axis is one of the six directions.
void add_stud(PartGeometry& g, const Transform& t) {
  if (auto d = stud_direction(t)) {
    // A stud engages by its top 4 LDU: some parts draw it longer, starting inside the body
    // (the front studs of an inverted slope), so its base is taken 4 LDU below its tip.
    Vec3 at = transformed(t, {0, -4, 0});
    at[size_t(axis_of(*d))] -= 4 * sign_of(*d);
    g.studs.push_back({at, *d});
  } else {
    ++g.angled_studs;
  }
}

// A type 3 or 4 line of `corners` corners (`rest`: from its colour on) as one or two triangles.
void add_face(PartGeometry& g, int corners, std::string_view rest) {
  next_token(rest);  // colour
  Vec3 p[4];
  for (int v = 0; v < corners; ++v)
    for (int a = 0; a < 3; ++a)
      if (!number(next_token(rest), p[v][a])) return;  // a malformed face draws nothing
  g.faces.push_back({{p[0], p[1], p[2]}});
  if (corners == 4) g.faces.push_back({{p[0], p[2], p[3]}});
}

// What a subfile (`sub`, its file name `base`) placed by `t` adds to the geometry of the file
// that places it: its faces, rounds, shafts and studs moved by `t`, and the files it misses.
void add_subfile(PartGeometry& g, const Transform& t, std::string_view base,
                 const PartGeometry& sub) {
  for (const Triangle& tri : sub.faces)
    g.faces.push_back(
        {{transformed(t, tri.p[0]), transformed(t, tri.p[1]), transformed(t, tri.p[2])}});
  // A Technic primitive is one shaft along its y axis, as long as it draws; what it is drawn
  // with is not another. A cylinder primitive's axis is its y from 0 to 1, its radius its x.
  // Shafts and rounds turned off the part's axes are left out.
  auto along_one_axis = [](const Vec3& a, const Vec3& b) {
    int axes = 0;
    for (int k = 0; k < 3; ++k) axes += std::abs(a[size_t(k)] - b[size_t(k)]) > 1e-3;
    return axes == 1;
  };
  auto take = [&](std::vector<Shaft>& into, const Shaft& s) {
    const Vec3 a = transformed(t, s.a), b = transformed(t, s.b);
    if (along_one_axis(a, b)) into.push_back({s.kind, a, b});
  };
  // A round's radius grows with what t does across its axis.
  auto take_round = [&](Round r, bool clip) {
    const int axis = Shaft{Shaft::Kind::Knuckle, r.a, r.b}.axis();
    const Vec3 a = transformed(t, r.a), b = transformed(t, r.b);
    if (!along_one_axis(a, b)) return;
    auto column = [&](int k) {
      return std::hypot(t.rot[size_t(k)], t.rot[3 + size_t(k)], t.rot[6 + size_t(k)]);
    };
    r.radius *= (column((axis + 1) % 3) + column((axis + 2) % 3)) / 2;
    if (r.radius < 2) return;
    r.a = a, r.b = b, r.clip = r.clip || clip;
    g.rounds.push_back(r);
  };
  const auto kind = shaft_primitive(base);
  if (const auto turn = cylinder_turn(base)) {
    take_round({{0, 0, 0}, {0, 1, 0}, 1, *turn, false}, false);
  } else if (!base.starts_with("stud") && !kind) {
    const bool clip = base.starts_with("clip");
    for (const Round& r : sub.rounds) take_round(r, clip);
  }
  if (kind) {
    double lo = 1e300, hi = -1e300;
    for (const Triangle& tri : sub.faces)
      for (const Vec3& p : tri.p) lo = std::min(lo, p[1]), hi = std::max(hi, p[1]);
    if (hi - lo < 1e-3) lo = 0, hi = 1;  // drawn flat: a unit length, as its scale gives
    take(g.shafts, {*kind, {0, lo, 0}, {0, hi, 0}});
  } else {
    for (const Shaft& s : sub.shafts) take(g.shafts, s);
  }
  for (const Connector& s : sub.studs) {
    // The stud's axis turned by t: its direction as a unit vector through the rotation.
    Vec3 axis{0, 0, 0};
    axis[size_t(axis_of(s.direction))] = sign_of(s.direction);
    Transform turn = t;
    turn.pos = {0, 0, 0};
    const auto direction = axis_direction(transformed(turn, axis));
    if (!direction) {
      ++g.angled_studs;
      continue;
    }
    g.studs.push_back({transformed(t, s.at), *direction});
  }
  g.angled_studs += sub.angled_studs;
  // Names, not occurrences: a missing file placed 20 times over 7 levels is one name.
  for (const auto& m : sub.missing) g.missing.push_back(m);
  std::sort(g.missing.begin(), g.missing.end());
  g.missing.erase(std::unique(g.missing.begin(), g.missing.end()), g.missing.end());
}

}  // namespace

std::shared_ptr<const PartGeometry> GeometryCache::flatten(const PartFile& file,
                                                           const FileFinder& find,
                                                           std::string& why) {
  if (auto it = done_.find(file.key); it != done_.end()) return it->second;
  if (auto it = failed_.find(file.key); it != failed_.end()) {
    why = it->second;
    return nullptr;
  }
  if (std::find(stack_.begin(), stack_.end(), file.key) != stack_.end()) {
    why = "its files refer to each other in a loop";
    return nullptr;
  }
  if (stack_.size() >= 32) {
    why = "its files are nested more than 32 deep";
    depth_failure_ = true;  // depends on where the file was reached from: not remembered
    return nullptr;
  }
  stack_.push_back(file.key);
  auto g = std::make_shared<PartGeometry>();
  bool first_line = true, failed = false;
  std::string moved_to;
  size_t references = 0;
  for_each_line(*file.text, [&](std::string_view raw) {
    if (failed) return;
    std::string_view rest = trim(raw);
    if (rest.empty()) return;
    const std::string_view type = next_token(rest);
    if (type == "0") {
      const std::string_view meta = trim(rest);
      // An MPD's embedded part file starts with its FILE line; the title is the line after.
      if (first_line && meta.starts_with("FILE ")) return;
      if (first_line) {
        g->title = std::string(meta);
        if (meta.starts_with("~Moved to ")) moved_to = std::string(trim(meta.substr(10)));
      } else if (meta.starts_with("!CATEGORY ")) {
        g->category = std::string(trim(meta.substr(10)));
      }
      first_line = false;
      return;
    }
    first_line = false;
    if (type == "3" || type == "4") {
      add_face(*g, type == "3" ? 3 : 4, rest);
      return;
    }
    if (type != "1") return;
    next_token(rest);  // colour
    Transform t;
    double v[12];
    for (double& x : v)
      if (!number(next_token(rest), x)) return;
    t.pos = {v[0], v[1], v[2]};
    std::copy(v + 3, v + 12, t.rot.begin());
    const std::string_view name = trim(rest);
    if (name.empty()) return;
    ++references;
    const std::string base = base_name(name);
    if (is_stud_primitive(base)) {
      add_stud(*g, t);
      return;
    }
    std::string sub_why;
    auto sub_file = find(name, sub_why);
    if (!sub_file) {
      g->missing.push_back(std::string(name));
      return;
    }
    auto sub = flatten(*sub_file, find, sub_why);
    if (!sub) {
      why = sub_why;
      failed = true;
      return;
    }
    if (const char* over = over_limits(*g, *sub)) {
      why = over;
      failed = true;
      return;
    }
    add_subfile(*g, t, base, *sub);
    if (!moved_to.empty() && references == 1) {  // a moved part is its target
      g->title = sub->title;
      g->category = sub->category;
    }
  });
  stack_.pop_back();
  if (failed) {
    if (!depth_failure_) failed_[file.key] = why;
    if (stack_.empty()) depth_failure_ = false;
    return nullptr;
  }
  std::sort(g->missing.begin(), g->missing.end());
  g->missing.erase(std::unique(g->missing.begin(), g->missing.end()), g->missing.end());
  if (g->category.empty()) {
    std::string_view title = without_title_marks(g->title);
    g->category = std::string(next_token(title));
  }
  done_[file.key] = g;
  return g;
}

}  // namespace lego::parts
