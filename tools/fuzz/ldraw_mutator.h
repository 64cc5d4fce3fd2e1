#pragma once
// A structure-aware mutator for LDraw text (issue 19): it edits what an LDraw file is made of
// (type-1 lines and their fields, matrices, colours, FILE blocks, references, steps, metas) the
// way hand-edited and tool-written files go wrong, and, less often, its bytes.
#include <cstdint>
#include <random>
#include <string>

namespace lego::fuzz {

using Rng = std::mt19937_64;

enum class LdrawMutation {
  Lines,       // delete, duplicate (up to 20,000 copies), swap, cut, extra tokens, positions
  Matrices,    // turns by any angle, two-decimal rotations, mirrors, scales, singular, nan
  Colours,     // codes LDraw has, codes it has not, direct colours, numbers out of range
  Files,       // FILE blocks: submodels, embedded parts, loops, fan-out, empty, duplicated names
  References,  // part names: real parts, missing ones, paths out of the library, devices
  Steps,       // STEP, ROTSTEP, thousands of steps, steps inside submodels
  Metas,       // BFC, !COLOUR, !CATEGORY, !LDRAW_ORG, titles in Latin-1, long comments
  Bytes,       // line endings (CR, CRLF), NUL, byte order marks, flipped and cut bytes
};
inline constexpr int kLdrawMutations = 8;
const char* name(LdrawMutation mutation);

// `seed` mutated by one to four edits of `mutation`, sometimes one of another kind after them.
std::string mutate_ldraw(const std::string& seed, LdrawMutation mutation, Rng& rng);

// Small models written here, beside whatever real files the driver reads as seeds: an MPD with a
// submodel, one with an embedded part drawn with stud primitives, a wall on a baseplate.
const std::string* builtin_ldraw_seeds(size_t& count);

}  // namespace lego::fuzz
