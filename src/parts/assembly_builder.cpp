#include "parts/assembly_builder.h"

#include <filesystem>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "core/lattice.h"
#include "core/text.h"

namespace lego::parts {
namespace {

// LDraw files write matrices with a few decimals: "0.57 0.82" is a rotation to a hundredth.
constexpr double kRotationTolerance = 1e-2;
// A rotation this close to a quarter turn (about a degree) is taken as that quarter turn.
constexpr double kQuarterTurnTolerance = 2e-2;
double dot3(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

using Matrix = std::array<double, 9>;  // row-major
Matrix product(const Matrix& a, const Matrix& b) {
  return Pose{a, {0, 0, 0}}.then(Pose{b, {0, 0, 0}}).rotation;
}
Matrix transposed(const Matrix& m) {
  return {m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]};
}

// m⁻¹ (row-major), or nullopt where its determinant is below `smallest` in size.
std::optional<std::array<double, 9>> inverted(const std::array<double, 9>& m, double smallest) {
  const double det = ldraw::Transform{{}, m}.determinant();
  if (!(std::abs(det) > smallest)) return std::nullopt;
  return std::array<double, 9>{(m[4] * m[8] - m[5] * m[7]) / det, (m[2] * m[7] - m[1] * m[8]) / det,
                               (m[1] * m[5] - m[2] * m[4]) / det, (m[5] * m[6] - m[3] * m[8]) / det,
                               (m[0] * m[8] - m[2] * m[6]) / det, (m[2] * m[3] - m[0] * m[5]) / det,
                               (m[3] * m[7] - m[4] * m[6]) / det, (m[1] * m[6] - m[0] * m[7]) / det,
                               (m[0] * m[4] - m[1] * m[3]) / det};
}

// Whether every entry of m is within `tolerance` of the orthogonal matrix nearest to it (its
// polar factor, by Newton's iteration R <- (R + R⁻ᵀ)/2).
bool near_orthogonal(const std::array<double, 9>& m, double tolerance) {
  std::array<double, 9> r = m;
  for (int it = 0; it < 20; ++it) {
    const auto inverse = inverted(r, 1e-9);
    if (!inverse) return false;
    const Matrix inverse_t = transposed(*inverse);
    double change = 0;
    std::array<double, 9> next;
    for (size_t k = 0; k < 9; ++k) {
      next[k] = (r[k] + inverse_t[k]) / 2;
      change = std::max(change, std::abs(next[k] - r[k]));
    }
    r = next;
    if (change < 1e-15) break;
  }
  for (size_t k = 0; k < 9; ++k)
    if (!(std::abs(m[k] - r[k]) <= tolerance)) return false;
  return true;
}

}  // namespace

std::optional<std::array<double, 9>> orthonormalized(const std::array<double, 9>& m,
                                                     double tolerance) {
  bool gram_near = true;  // MᵀM within `tolerance` of I
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double d = 0;
      for (int k = 0; k < 3; ++k) d += m[size_t(3 * k + i)] * m[size_t(3 * k + j)];
      gram_near = gram_near && std::abs(d - (i == j ? 1.0 : 0.0)) <= tolerance;
    }
  // Within `tolerance` of a rotation, entry by entry: two decimals of a turn ("-0.47 0 -0.89")
  // are within 0.005 of it, while MᵀM strays twice as far (1.013).
  if (!gram_near && !near_orthogonal(m, tolerance)) return std::nullopt;
  // Gram-Schmidt on the columns (the part's axes in the world), in order.
  double c[3][3];
  for (int j = 0; j < 3; ++j)
    for (int r = 0; r < 3; ++r) c[j][r] = m[size_t(3 * r + j)];
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < j; ++i) {
      const double d = dot3(c[j], c[i]);
      for (int r = 0; r < 3; ++r) c[j][r] -= d * c[i][r];
    }
    const double length = std::sqrt(dot3(c[j], c[j]));
    for (int r = 0; r < 3; ++r) c[j][r] /= length;
  }
  std::array<double, 9> out;
  for (int j = 0; j < 3; ++j)
    for (int r = 0; r < 3; ++r) out[size_t(3 * r + j)] = c[j][r];
  return out;
}

std::optional<std::array<double, 9>> quarter_turn(const std::array<double, 9>& m,
                                                  double tolerance) {
  std::array<double, 9> out{};
  bool column_used[3] = {false, false, false};
  for (int r = 0; r < 3; ++r) {
    int found = -1;
    for (int k = 0; k < 3; ++k) {
      const double v = m[size_t(3 * r + k)];
      if (std::abs(std::abs(v) - 1) <= tolerance) {
        if (found >= 0 || column_used[k]) return std::nullopt;
        found = k;
      } else if (std::abs(v) > tolerance) {
        return std::nullopt;
      }
    }
    if (found < 0) return std::nullopt;
    column_used[found] = true;
    out[size_t(3 * r + found)] = m[size_t(3 * r + found)] > 0 ? 1 : -1;
  }
  return out;
}

std::optional<std::array<double, 9>> model_frame(const ldraw::Model& model) {
  // Each part votes for the turn left when its own quarter turns are taken out: R·Pᵀ for the
  // signed permutation P nearest to its rotation R.
  std::map<std::array<long, 9>, std::pair<int, std::array<double, 9>>> votes;
  for (const ldraw::PlacedPart& p : model.parts) {
    auto r = orthonormalized(p.transform.rot, kRotationTolerance);
    if (!r) continue;
    std::array<double, 9> perm{};
    bool used[3] = {false, false, false}, ok = true;
    for (int row = 0; row < 3 && ok; ++row) {
      int best = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs((*r)[size_t(3 * row + k)]) > std::abs((*r)[size_t(3 * row + best)])) best = k;
      ok = !used[best] && std::abs((*r)[size_t(3 * row + best)]) > 0.8;
      used[best] = true;
      perm[size_t(3 * row + best)] = (*r)[size_t(3 * row + best)] > 0 ? 1 : -1;
    }
    if (!ok) continue;
    const Matrix q = product(*r, transposed(perm));  // R·Pᵀ
    std::array<long, 9> key;
    for (int k = 0; k < 9; ++k) key[size_t(k)] = std::lround(q[size_t(k)] * 100);
    auto& v = votes[key];
    ++v.first;
    v.second = q;
  }
  const std::array<long, 9> identity{100, 0, 0, 0, 100, 0, 0, 0, 100};
  int best = 0, at_identity = 0;
  std::optional<std::array<double, 9>> frame;
  for (const auto& [key, vote] : votes) {
    if (key == identity)
      at_identity = vote.first;
    else if (vote.first > best)
      best = vote.first, frame = vote.second;
  }
  // Only a turn about the vertical, or a slight tilt: gravity stays along the frame's y.
  if (!frame || best <= at_identity || (*frame)[4] < std::cos(10 * M_PI / 180)) return std::nullopt;
  return orthonormalized(*frame, kRotationTolerance);
}

namespace {

// Where the model's plates lie: the height (LDU, in [0, 8)) modulo a plate that most upright
// parts' origins share.
double plate_offset(const ldraw::Model& model,
                    const std::function<ldraw::Transform(const ldraw::Transform&)>& in_frame) {
  std::map<long, int> votes;  // by hundredths of an LDU
  for (const ldraw::PlacedPart& p : model.parts) {
    const ldraw::Transform t = in_frame(p.transform);
    if (std::abs(std::abs(t.rot[4]) - 1) > kQuarterTurnTolerance) continue;  // not upright
    ++votes[residue_hundredths(t.pos[1], kLduPerPlate)];
  }
  long best = 0;
  int most = 0;
  for (const auto& [residue, count] : votes)
    if (count > most) most = count, best = residue;
  return double(best) / 100;
}

// docs/what-it-analyses.md, turned lattices: a part turned by an angle that is not a multiple of
// 90 degrees lies on a lattice of its own when a submodel placement turned it: the outermost
// placement whose turn is not a quarter turn (`outer`, in the model's frame) is that lattice, and
// what lies inside it (its file's exact numbers) must place the part on a quarter turn there.
struct FramedPart {
  LatticeFrame frame;
  Pose pose;
};
// The main file's own lattice is such a frame where the model is analysed turned (model_frame)
// and a part of the main file is not (the outvoted bricks beside a turned building).
constexpr int kMainFileFrame = -2;  // Model::placements count from 0
std::optional<FramedPart> turned_frame(const ldraw::Model& model, const ldraw::PlacedPart& p,
                                       ldraw::Transform outer) {
  std::vector<int> inside;  // the placements holding it, outermost first
  for (int k = p.inside; k >= 0; k = model.placements[size_t(k)].parent) inside.push_back(k);
  std::reverse(inside.begin(), inside.end());
  auto placed = [&](size_t k) -> const ldraw::Transform& {
    return model.placements[size_t(inside[k])].transform;
  };
  for (size_t j = 0; j <= inside.size(); ++j) {  // j = 0: the main file; j: inside[j - 1]
    if (j > 0) outer = outer.then(placed(j - 1));
    const auto turn = orthonormalized(outer.rot, kRotationTolerance);
    if (!turn) return std::nullopt;
    if (quarter_turn(*turn, kQuarterTurnTolerance)) continue;
    ldraw::Transform inner;
    for (size_t k = j; k < inside.size(); ++k) inner = inner.then(placed(k));
    inner = inner.then(p.local);
    const auto rotation = orthonormalized(inner.rot, 1e-6);
    const auto quarter = rotation ? quarter_turn(*rotation, 1e-6) : std::nullopt;
    if (!quarter) return std::nullopt;
    FramedPart out;
    out.frame.id = j == 0 ? kMainFileFrame : inside[j - 1];
    out.frame.pose.rotation = *turn;
    out.frame.pose.origin = outer.pos;
    out.pose.rotation = *quarter;
    out.pose.origin = inner.pos;
    return out;
  }
  return std::nullopt;
}

// Frames of parts turned on their own lines count down from here (turned_frame's from 0 up).
constexpr int kFirstPartTurnFrame = -3;

// docs/what-it-analyses.md, turned lattices: parts that the file turns one by one, each on its
// own line, share a lattice where their turns agree up to quarter turns (the mosque's walls, each
// brick's line turned 30 degrees). The lattice is placed where its first part is; the others lie
// on it where the file's own numbers put them: their offsets are taken back through their written
// matrices, the way the author computed them ("0.87 0 0.5" and an offset of 52.2 for three
// studs, not the 51.96 of an exact 30 degrees).
class PartTurnLattices {
 public:
  // `rotation`: the part's, made orthonormal; `written`: its placement as the file writes it.
  std::optional<FramedPart> place(const std::array<double, 9>& rotation,
                                  const ldraw::Transform& written) {
    for (size_t g = 0; g < lattices_.size(); ++g) {
      const Matrix relative = product(transposed(lattices_[g].rotation), rotation);  // Qᵀ·R
      if (const auto quarter = quarter_turn(relative, kSameTurn))
        return on_lattice(int(g), *quarter, written);
    }
    // A new lattice: upright and proper, the part keeping on it the quarter turn (perhaps on its
    // side, upside down or mirrored) that makes it so. Only turns about the vertical: on a
    // lattice tilted part by part (a droid leaning 9 degrees on its hinge), PHYSICS.md's support
    // force holds no twist about the studs, and such parts stay carried as before.
    std::array<double, 9> own{};
    Pose lattice{rotation, written.pos};
    double most_up = -2;
    const double hand = ldraw::Transform{{}, rotation}.determinant() < 0 ? -1 : 1;
    constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                   {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& order : kOrders)
      for (int signs = 0; signs < 8; ++signs) {
        std::array<double, 9> p{};
        for (int r = 0; r < 3; ++r) p[size_t(3 * r + order[r])] = (signs >> r & 1) ? -1 : 1;
        if (ldraw::Transform{{}, p}.determinant() != hand) continue;
        const Matrix q = product(rotation, transposed(p));  // R·Pᵀ
        if (q[4] > most_up) most_up = q[4], own = p, lattice.rotation = q;
      }
    if (tilted(LatticeFrame{0, lattice})) return std::nullopt;
    lattices_.push_back(lattice);
    return on_lattice(int(lattices_.size() - 1), own, written);
  }

 private:
  // Turns this close (matrix entries, about a tenth of a degree) are one lattice's: two decimals
  // written in two orders ("0.87 0 0.5", "0.5 0 -0.87") agree to a few thousandths of a degree.
  static constexpr double kSameTurn = 2e-3;

  // The part on lattice g, turned there by `quarter`. Its origin there is P·W⁻¹·(p − o) as the
  // author computed it, where that lies on whole LDU as parts on a lattice do; else (a ring of
  // bricks, each at its own angle, two of them a quarter turn apart) exactly where it is drawn,
  // Qᵀ·(p − o).
  std::optional<FramedPart> on_lattice(int g, const std::array<double, 9>& quarter,
                                       const ldraw::Transform& written) const {
    const auto inverse = inverted(written.rot, 0.5);
    if (!inverse) return std::nullopt;
    const Pose& lattice = lattices_[size_t(g)];
    Vec3 offset{}, drawn{};
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        const double d = written.pos[size_t(k)] - lattice.origin[size_t(k)];
        offset[size_t(r)] += (*inverse)[size_t(3 * r + k)] * d;
        drawn[size_t(r)] += lattice.rotation[size_t(3 * k + r)] * d;
      }
    const Vec3 computed = Pose{quarter, {0, 0, 0}}.apply(offset);
    auto on_grid = [](double v) { return std::abs(v - std::round(v)) <= kOnGrid; };
    FramedPart out;
    out.frame.id = kFirstPartTurnFrame - g;
    out.frame.pose = lattice;
    out.pose.rotation = quarter;
    out.pose.origin =
        on_grid(computed[0]) && on_grid(computed[1]) && on_grid(computed[2]) ? computed : drawn;
    return out;
  }

  // Positions are written with two decimals.
  static constexpr double kOnGrid = 0.03;

  std::vector<Pose> lattices_;
};

// Where a known part goes: a brick with its pose (on the model's lattice or on a lattice turned
// with it), or carried, with the role that says why.
struct Placement {
  Pose pose;
  std::optional<FramedPart> framed;
  std::optional<PartRole> carried;
  bool approximate = false;  // its matrix a rotation only to kRotationTolerance
};

// `placed`: the part's transform in the model's frame.
Placement place(const ldraw::Model& model, const ldraw::PlacedPart& p,
                const ldraw::Transform& placed, const PartKnowledge& k,
                const ldraw::Transform& model_turn, PartTurnLattices& part_turns) {
  Placement out;
  out.carried = k.carried;
  std::array<double, 9> rotation = placed.rot;
  if (auto exact = orthonormalized(rotation, 1e-6)) {
    rotation = *exact;
  } else if (auto near = orthonormalized(rotation, kRotationTolerance)) {
    rotation = *near;
    out.approximate = true;
  } else if (!out.carried) {
    out.carried = PartRole::ScaledOrSheared;
  }
  std::optional<std::array<double, 9>> turn;
  if (!out.carried) {
    turn = quarter_turn(rotation, kQuarterTurnTolerance);
    if (!turn) out.framed = turned_frame(model, p, model_turn);
    if (!turn && !out.framed) out.framed = part_turns.place(rotation, placed);
    if (!turn && !out.framed) out.carried = PartRole::TurnedOffQuarter;
  }
  out.pose.rotation = turn ? *turn : rotation;
  out.pose.origin = placed.pos;
  if (out.framed) out.pose = out.framed->pose;
  if (out.carried && !orthonormalized(placed.rot, kRotationTolerance))
    out.pose.rotation = placed.rot;
  return out;
}

}  // namespace

AssemblyConversion to_assembly(const ldraw::Model& model, PartLibrary& library,
                               const std::vector<size_t>& fixed_parts, const Budget* budget) {
  AssemblyConversion out;
  EmbeddedParts embedded(model);
  // A model drawn turned as a whole (a car tilted 1° on its springs) is analysed in its own frame.
  const auto frame = model_frame(model);
  if (frame)
    out.diagnostics.push_back(
        {ldraw::Severity::Warning, model.source, 0,
         fmt::format(
             "most parts are turned together by {:.1f} degrees: analysed in that frame, "
             "with gravity along its down axis",
             std::acos(std::clamp(((*frame)[0] + (*frame)[4] + (*frame)[8] - 1) / 2, -1.0, 1.0)) *
                 180 / M_PI)});
  auto in_frame = [&](const ldraw::Transform& t) {
    if (!frame) return t;
    const Pose back = Pose{transposed(*frame), {0, 0, 0}}.then(Pose{t.rot, t.pos});  // Fᵀ·t
    return ldraw::Transform{back.origin, back.rotation};
  };
  out.plates = plate_offset(model, in_frame);
  const ldraw::Transform model_turn = in_frame(ldraw::Transform{});  // Fᵀ: where lattices start
  PartTurnLattices part_turns;
  // The same part placed twice in one place (a common slip in LDraw editors, which draw one): the
  // copies are left out, each naming the first, so that they neither weigh nor collide.
  std::map<std::string, size_t> first_at;
  auto place_key = [](const ldraw::PlacedPart& p) {
    std::string key = p.part;
    for (double v : p.transform.pos) key += fmt::format(" {}", std::llround(v * 100));
    for (double v : p.transform.rot) key += fmt::format(" {}", std::llround(v * 1000));
    return key;
  };
  for (size_t i = 0; i < model.parts.size(); ++i) {
    if (budget && i % 256 == 0) budget->check(kPartKnowledge, i, model.parts.size());
    const ldraw::PlacedPart& p = model.parts[i];
    if (auto [at, fresh] = first_at.try_emplace(place_key(p), i); !fresh) {
      const ldraw::PlacedPart& first = model.parts[at->second];
      out.skipped.push_back(
          {i, PartRole::Copy,
           fmt::format("a copy of {}:{}, the same part in the same place",
                       std::filesystem::path(first.file).filename().string(), first.line)});
      continue;
    }
    const ldraw::Transform placed = in_frame(p.transform);
    std::string why;
    const PartKnowledge* k = library.knowledge(p, embedded, why);
    if (!k) {
      const std::string ext = ascii_lower(std::filesystem::path(p.reference).extension().string());
      const bool submodel = ext == ".ldr" || ext == ".mpd" || ext == ".l3b";
      if (submodel)
        why = fmt::format("missing submodel '{}': in neither the file, its folder nor the library",
                          p.reference);
      out.skipped.push_back({i, submodel ? PartRole::MissingSubmodel : PartRole::UnknownPart, why});
      continue;
    }
    const SourceRef source{p.file, p.line, p.step, p.built_in, p.apart_from};
    const Placement at = place(model, p, placed, *k, model_turn, part_turns);
    if (at.carried) {
      out.assembly.carried.push_back(carried_part(k->type, *at.carried, p.color, source, at.pose));
      out.carried_part.push_back(i);
      continue;
    }
    if (at.approximate && !at.framed)  // said where the verdict relies on it
      out.diagnostics.push_back(
          {ldraw::Severity::Warning, p.file, p.line,
           "its matrix is a rotation only to 1e-2 (a few decimals): taken as the rotation it is "
           "nearest to"});
    const BrickType* type = out.types->find(k->type.part);
    if (!type) type = &out.types->add(k->type);
    Brick b;
    b.type = type;
    b.pose = at.pose;
    if (at.framed) b.frame = at.framed->frame;
    b.color = p.color;
    b.source = source;
    b.fixed = std::find(fixed_parts.begin(), fixed_parts.end(), i) != fixed_parts.end();
    out.assembly.bricks.push_back(b);
    out.brick_part.push_back(i);
  }
  return out;
}

}  // namespace lego::parts
