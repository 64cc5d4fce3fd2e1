#include "ldraw_mutator.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

namespace lego::fuzz {
namespace {

template <class T, size_t N>
const T& pick(const std::array<T, N>& items, Rng& rng) {
  return items[rng() % N];
}

bool chance(Rng& rng, double p) {
  return std::uniform_real_distribution<double>(0, 1)(rng) < p;
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  for (char c : text) {
    if (c == '\n') {
      lines.push_back(line);
      line.clear();
    } else {
      line += c;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + '\n';
  return text;
}

std::vector<std::string> tokens_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

std::string join_tokens(const std::vector<std::string>& tokens) {
  std::string out;
  for (const auto& t : tokens) out += (out.empty() ? "" : " ") + t;
  return out;
}

// Indices of the type-1 lines with all their 15 fields.
std::vector<size_t> part_lines(const std::vector<std::string>& lines) {
  std::vector<size_t> out;
  for (size_t i = 0; i < lines.size(); ++i) {
    auto t = tokens_of(lines[i]);
    if (t.size() >= 15 && t[0] == "1") out.push_back(i);
  }
  return out;
}

std::string number(double v) {
  return fmt::format("{}", v);
}

constexpr std::array<const char*, 20> kStrangeNumbers = {"nan",
                                                         "-nan",
                                                         "inf",
                                                         "-inf",
                                                         "1e308",
                                                         "-1e308",
                                                         "1e999",
                                                         "1e-320",
                                                         "0",
                                                         "-0",
                                                         "99999999999999999999",
                                                         "2147483648",
                                                         "-2147483649",
                                                         "1e6",
                                                         "3e9",
                                                         "7.3",
                                                         "0x10",
                                                         "",
                                                         "1,5",
                                                         "1e"};

std::string strange_number(Rng& rng) {
  return pick(kStrangeNumbers, rng);
}

// A 3x3 matrix, row-major, as LDraw writes it.
std::array<double, 9> rotation(double ax, double ay, double az) {
  const double cx = std::cos(ax), sx = std::sin(ax), cy = std::cos(ay), sy = std::sin(ay),
               cz = std::cos(az), sz = std::sin(az);
  return {cy * cz,
          -cy * sz,
          sy,
          sx * sy * cz + cx * sz,
          -sx * sy * sz + cx * cz,
          -sx * cy,
          -cx * sy * cz + sx * sz,
          cx * sy * sz + sx * cz,
          cx * cy};
}

std::array<std::string, 9> matrix_text(Rng& rng) {
  std::uniform_int_distribution<int> quarter(0, 3);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  const double q = M_PI / 2;
  std::array<double, 9> m;
  std::array<std::string, 9> out;
  int decimals = 6;
  switch (rng() % 8) {
    case 0:  // a quarter turn about any axes
      m = rotation(q * quarter(rng), q * quarter(rng), q * quarter(rng));
      break;
    case 1:  // any angle about the vertical
      m = rotation(0, angle(rng), 0);
      break;
    case 2:  // any angle at all
      m = rotation(angle(rng), angle(rng), angle(rng));
      break;
    case 3:  // a quarter turn written with two decimals and a hair off
      m = rotation(q * quarter(rng) + 0.004, q * quarter(rng), 0.003);
      decimals = 2;
      break;
    case 4:  // mirrored or scaled
      m = rotation(0, q * quarter(rng), 0);
      for (int k = 0; k < 3; ++k) m[size_t(3 * k + rng() % 3)] *= chance(rng, 0.5) ? -1 : 2.5;
      break;
    case 5:  // singular
      m = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      if (chance(rng, 0.5)) m[0] = m[4] = 1;
      break;
    case 6:  // a rotation with one strange entry
      m = rotation(0, q * quarter(rng), 0);
      for (int k = 0; k < 9; ++k) out[size_t(k)] = fmt::format("{:.{}f}", m[size_t(k)], decimals);
      out[rng() % 9] = strange_number(rng);
      return out;
    default:  // huge
      m = rotation(0, q * quarter(rng), 0);
      for (double& v : m) v *= 1e300;
  }
  for (int k = 0; k < 9; ++k) out[size_t(k)] = fmt::format("{:.{}f}", m[size_t(k)], decimals);
  if (m[0] > 1e100 || m[4] > 1e100 || m[8] > 1e100)
    for (int k = 0; k < 9; ++k) out[size_t(k)] = number(m[size_t(k)]);
  return out;
}

constexpr std::array<const char*, 22> kColours = {
    "16",          "24",         "0",   "4",         "15",        "71",    "72",      "256",
    "511",         "4294967295", "-1",  "0x2FF0000", "0x3FF00FF", "0x2GG", "#FF0000", "47",
    "99999999999", "abc",        "1.5", "334",       "10000",     "32"};

constexpr std::array<const char*, 26> kParts = {
    "3001.dat",  "3004.dat", "3024.dat",     "3040b.dat",  "3039.dat",      "4070.dat",
    "6141.dat",  "3811.dat", "30383.dat",    "3062b.dat",  "973.dat",       "87081.dat",
    "4742.dat",  "3005.dat", "3622.dat",     "2431.dat",   "s/3001s01.dat", "stud.dat",
    "3941.dat",  "4589.dat", "3626bp01.dat", "30027b.dat", "3068b.dat",     "3020.dat",
    "87087.dat", "60594.dat"};

constexpr std::array<const char*, 16> kBadReferences = {"missing.dat",
                                                        "../../../etc/passwd",
                                                        "/dev/zero",
                                                        "/dev/urandom",
                                                        "C:\\LDraw\\parts\\3001.dat",
                                                        "PARTS\\3001.DAT",
                                                        "P\\STUD.DAT",
                                                        "a b c.dat",
                                                        "caf\xe9.dat",
                                                        "3001",
                                                        "3001.DAT",
                                                        ".dat",
                                                        "s\\",
                                                        "\\\\server\\share\\x.dat",
                                                        "fifo.dat",
                                                        "sub.ldr"};

std::string part_line(Rng& rng, const std::string& part) {
  std::uniform_int_distribution<int> cell(-6, 6);
  const auto m = matrix_text(rng);
  std::string line = fmt::format("1 {} {} {} {}", pick(kColours, rng), 20 * cell(rng),
                                 -8 * cell(rng), 20 * cell(rng));
  // Mostly plain turns: a model of strange matrices only reaches the carried-part paths.
  if (chance(rng, 0.6)) return line + " 1 0 0 0 1 0 0 0 1 " + part;
  for (const auto& v : m) line += " " + v;
  return line + " " + part;
}

// A type-1 line to edit, at random; when there is none, one is added instead.
std::optional<size_t> some_part_line(std::vector<std::string>& lines, Rng& rng) {
  const auto parts = part_lines(lines);
  if (!parts.empty()) return parts[rng() % parts.size()];
  lines.push_back(part_line(rng, pick(kParts, rng)));
  return std::nullopt;
}

// An embedded part file: a body of quads and studs, sometimes tubes, a baseplate, fan-out.
std::vector<std::string> embedded_part(Rng& rng, const std::string& name) {
  std::vector<std::string> out = {"0 FILE " + name, "0 Embedded part " + name, "0 Name: " + name,
                                  "0 !LDRAW_ORG Part UPDATE 2026-01"};
  if (chance(rng, 0.2)) out.push_back("0 !CATEGORY Baseplate");
  std::uniform_int_distribution<int> size(1, 6);
  const int w = size(rng), l = size(rng);
  const int h = chance(rng, 0.5) ? 8 : 24;
  out.push_back(fmt::format("4 16 {} 0 {} {} 0 {} {} 0 {} {} 0 {}", -10 * l, -10 * w, 10 * l,
                            -10 * w, 10 * l, 10 * w, -10 * l, 10 * w));
  out.push_back(fmt::format("4 16 {} {} {} {} {} {} {} {} {} {} {} {}", -10 * l, h, -10 * w, 10 * l,
                            h, -10 * w, 10 * l, h, 10 * w, -10 * l, h, 10 * w));
  for (int x = 0; x < l; ++x)
    for (int z = 0; z < w; ++z)
      out.push_back(fmt::format("1 16 {} 0 {} 1 0 0 0 1 0 0 0 1 stud.dat", 20 * x - 10 * (l - 1),
                                20 * z - 10 * (w - 1)));
  if (chance(rng, 0.5))
    out.push_back(fmt::format("1 16 0 {} 0 1 0 0 0 1 0 0 0 1 stud4.dat", h - 4));
  if (chance(rng, 0.15))  // fan-out: twenty copies of a part that places twenty copies of ...
    for (int k = 0; k < 20; ++k)
      out.push_back(fmt::format("1 16 {} 0 0 1 0 0 0 1 0 0 0 1 {}", k,
                                chance(rng, 0.5) ? name : "s/3001s01.dat"));
  if (chance(rng, 0.1))  // a part 1e6 studs wide
    out.push_back("4 16 -2e7 0 -2e7 2e7 0 -2e7 2e7 24 2e7 -2e7 24 2e7");
  out.push_back("0 NOFILE");
  return out;
}

void mutate_lines(std::vector<std::string>& lines, Rng& rng) {
  if (lines.empty()) {
    lines.push_back(part_line(rng, pick(kParts, rng)));
    return;
  }
  const size_t i = rng() % lines.size();
  switch (rng() % 7) {
    case 0:
      lines.erase(lines.begin() + long(i));
      break;
    case 1: {  // copies: a few, or very many
      // 20,000, not the 100,000 of the test that pins copies (CopiesOfAPartInOnePlace...): read
      // under the sanitizers, 100,000 took 24 s of the fuzz step's 30.
      const size_t copies = chance(rng, 0.02) ? 20000 : 1 + rng() % 5;
      const std::string line = lines[i];
      lines.insert(lines.begin() + long(i), copies, line);
      break;
    }
    case 2:
      std::swap(lines[i], lines[rng() % lines.size()]);
      break;
    case 3: {  // cut after a token
      auto t = tokens_of(lines[i]);
      if (!t.empty()) t.resize(rng() % t.size());
      lines[i] = join_tokens(t);
      break;
    }
    case 4:
      lines[i].append(chance(rng, 0.5) ? " extra tokens" : " 1 2 3");
      break;
    case 5: {  // a position far away, off the lattice, or not a number
      const auto p = some_part_line(lines, rng);
      if (!p) break;
      auto t = tokens_of(lines[*p]);
      const size_t field = 2 + rng() % 3;
      std::uniform_real_distribution<double> off(-1000, 1000);
      t[field] = chance(rng, 0.5) ? strange_number(rng) : fmt::format("{:.3f}", off(rng));
      lines[*p] = join_tokens(t);
      break;
    }
    default: {  // a line of another type
      std::uniform_real_distribution<double> v(-100, 100);
      const int type = 2 + int(rng() % 4);
      std::string l = fmt::format("{} 24", type);
      for (int k = 0; k < 3 * std::min(type, 4); ++k)  // 2, 3 or 4 points
        l += fmt::format(" {}",
                         chance(rng, 0.05) ? strange_number(rng) : fmt::format("{:.2f}", v(rng)));
      lines.insert(lines.begin() + long(i), l);
    }
  }
}

void mutate_matrix(std::vector<std::string>& lines, Rng& rng) {
  const auto i = some_part_line(lines, rng);
  if (!i) return;
  auto t = tokens_of(lines[*i]);
  const auto m = matrix_text(rng);
  for (int k = 0; k < 9; ++k) t[size_t(5 + k)] = m[size_t(k)];
  lines[*i] = join_tokens(t);
}

void mutate_colour(std::vector<std::string>& lines, Rng& rng) {
  if (lines.empty()) return;
  const size_t i = rng() % lines.size();
  auto t = tokens_of(lines[i]);
  if (t.size() < 2 || t[0] == "0") {
    lines.insert(lines.begin() + long(i), part_line(rng, pick(kParts, rng)));
    return;
  }
  t[1] = pick(kColours, rng);
  lines[i] = join_tokens(t);
}

void mutate_files(std::vector<std::string>& lines, Rng& rng) {
  static const std::array<const char*, 8> kNames = {"sub.ldr",  "sub.ldr", "main.ldr",    "x.dat",
                                                    "part.dat", "SUB.LDR", "caf\xe9.ldr", ""};
  const std::string sub = pick(kNames, rng);
  std::vector<std::string> block;
  switch (rng() % 5) {
    case 0:  // a submodel and a reference to it
      block = {"0 FILE " + sub, "0 " + sub};
      for (int k = 0, n = 1 + int(rng() % 4); k < n; ++k)
        block.push_back(part_line(rng, pick(kParts, rng)));
      if (chance(rng, 0.3)) block.push_back("0 STEP");
      block.push_back("0 NOFILE");
      lines.push_back(part_line(rng, sub));
      break;
    case 1:  // an embedded part
      block = embedded_part(rng, sub.empty() ? "e.dat" : sub);
      lines.push_back(part_line(rng, sub.empty() ? "e.dat" : sub));
      break;
    case 2:  // a loop: the submodel places the file that places it
      block = {"0 FILE a.ldr", part_line(rng, "b.ldr"), "0 FILE b.ldr", part_line(rng, "a.ldr"),
               part_line(rng, "3001.dat")};
      lines.push_back(part_line(rng, "a.ldr"));
      break;
    case 3:  // an empty FILE, or one without a name
      block = {"0 FILE " + sub};
      if (chance(rng, 0.5)) block.push_back("0 NOFILE");
      break;
    default:  // the first line a FILE: the whole text becomes an MPD
      lines.insert(lines.begin(), "0 FILE " + sub);
      return;
  }
  const size_t at = chance(rng, 0.7) ? lines.size() : rng() % (lines.size() + 1);
  lines.insert(lines.begin() + long(at), block.begin(), block.end());
}

void mutate_reference(std::vector<std::string>& lines, Rng& rng) {
  const auto i = some_part_line(lines, rng);
  if (!i) return;
  auto t = tokens_of(lines[*i]);
  t.resize(14);
  std::string name;
  switch (rng() % 4) {
    case 0:
    case 1:
      name = pick(kParts, rng);
      break;
    case 2:
      name = pick(kBadReferences, rng);
      break;
    default:
      name = chance(rng, 0.5) ? std::string(5000, 'x') + ".dat" : "main.ldr";
  }
  lines[*i] = join_tokens(t) + " " + name;
}

void mutate_steps(std::vector<std::string>& lines, Rng& rng) {
  static const std::array<const char*, 6> kSteps = {"0 STEP",
                                                    "0 STEP",
                                                    "0 ROTSTEP 0 90 0 ABS",
                                                    "0 ROTSTEP END",
                                                    "0 !LPUB PAGE SIZE 8 11",
                                                    "0 ROTSTEP nan 1e999 0 REL"};
  if (chance(rng, 0.03)) {  // ten thousand steps
    std::vector<std::string> many;
    for (int k = 0; k < 10000; ++k) {
      many.push_back(part_line(rng, "3024.dat"));
      many.push_back("0 STEP");
    }
    lines.insert(lines.end(), many.begin(), many.end());
    return;
  }
  for (int k = 0, n = 1 + int(rng() % 5); k < n; ++k)
    lines.insert(lines.begin() + long(rng() % (lines.size() + 1)), pick(kSteps, rng));
}

void mutate_metas(std::vector<std::string>& lines, Rng& rng) {
  static const std::array<const char*, 16> kMetas = {
      "0 BFC INVERTNEXT",
      "0 BFC CERTIFY CCW",
      "0 !COLOUR Fuzz CODE 999 VALUE #FF0000 EDGE #000000",
      "0 !COLOUR Fuzz CODE 4 VALUE #GG0000 EDGE",
      "0 !CATEGORY Baseplate",
      "0 !LDRAW_ORG Baseplate UPDATE 2004-03",
      "0 Name: caf\xe9.ldr",
      "0 Author: J\xf6rg",
      "0 T\xedtulo",
      "0 !HISTORY 2026-01-01 [x] \xff\xfe",
      "0 GHOST 1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat",
      "0 MLCAD HIDE 1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat",
      "0 MLCAD BTG group",
      "0 !TEXMAP START PLANAR 0 0 0 1 0 0 0 1 0 tex.png",
      "0 //",
      "0 !KEYWORDS"};
  if (chance(rng, 0.05))
    lines.insert(lines.begin(), "0 " + std::string(100000, chance(rng, 0.5) ? 'x' : '\xe9'));
  else
    lines.insert(lines.begin() + long(rng() % (lines.size() + 1)), pick(kMetas, rng));
}

std::string mutate_bytes(std::string text, Rng& rng) {
  switch (rng() % 8) {
    case 0: {  // old Mac line endings
      for (char& c : text)
        if (c == '\n') c = '\r';
      return text;
    }
    case 1: {
      std::string out;
      for (char c : text) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
      return out;
    }
    case 2:
      return "\xef\xbb\xbf" + text;
    case 3:
      return "\xff\xfe" + text;
    default:
      break;
  }
  for (int e = 0, edits = 1 + int(rng() % 6); e < edits; ++e) {
    const size_t pos = text.empty() ? 0 : rng() % (text.size() + 1);
    switch (rng() % 4) {
      case 0:
        if (pos < text.size()) text[pos] = char(rng() % 256);
        break;
      case 1:
        if (pos < text.size()) text.erase(pos, 1 + rng() % 40);
        break;
      case 2:
        text.insert(pos, 1, chance(rng, 0.5) ? '\0' : char(rng() % 256));
        break;
      default:
        text.resize(pos);
    }
  }
  return text;
}

// In the order of LdrawMutation; Bytes works on the text, not its lines.
using LineMutator = void (*)(std::vector<std::string>&, Rng&);
constexpr LineMutator kLineMutators[] = {mutate_lines, mutate_matrix,    mutate_colour,
                                         mutate_files, mutate_reference, mutate_steps,
                                         mutate_metas};
static_assert(std::size(kLineMutators) == kLdrawMutations - 1);

std::string apply(const std::string& text, LdrawMutation mutation, Rng& rng) {
  if (mutation == LdrawMutation::Bytes) return mutate_bytes(text, rng);
  auto lines = split_lines(text);
  kLineMutators[int(mutation)](lines, rng);
  return join_lines(lines);
}

}  // namespace

const char* name(LdrawMutation mutation) {
  static const char* names[kLdrawMutations] = {"lines",      "matrices", "colours", "files",
                                               "references", "steps",    "metas",   "bytes"};
  return names[int(mutation)];
}

std::string mutate_ldraw(const std::string& seed, LdrawMutation mutation, Rng& rng) {
  std::string text = seed;
  for (int k = 0, edits = 1 + int(rng() % 4); k < edits; ++k) text = apply(text, mutation, rng);
  if (chance(rng, 0.2)) text = apply(text, LdrawMutation(rng() % kLdrawMutations), rng);
  return text;
}

const std::string* builtin_ldraw_seeds(size_t& count) {
  static const std::string seeds[] = {
      "0 FILE main.ldr\n0 Main\n0 Name: main.ldr\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 sub.ldr\n"
      "1 1 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n1 14 20 -48 0 0 0 1 0 1 0 -1 0 0 3004.dat\n"
      "0 NOFILE\n0 FILE sub.ldr\n0 Sub\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 3020.dat\n0 STEP\n"
      "1 16 0 -8 0 1 0 0 0 1 0 0 0 1 3024.dat\n0 NOFILE\n",
      "0 FILE main.ldr\n1 4 0 0 0 1 0 0 0 1 0 0 0 1 e.dat\n1 2 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "0 FILE e.dat\n0 Embedded brick\n0 Name: e.dat\n0 !LDRAW_ORG Part\n"
      "4 16 -40 0 -20 40 0 -20 40 0 20 -40 0 20\n4 16 -40 24 -20 40 24 -20 40 24 20 -40 24 20\n"
      "1 16 -30 0 -10 1 0 0 0 1 0 0 0 1 stud.dat\n1 16 -10 0 -10 1 0 0 0 1 0 0 0 1 stud.dat\n"
      "1 16 10 0 -10 1 0 0 0 1 0 0 0 1 stud.dat\n1 16 30 0 -10 1 0 0 0 1 0 0 0 1 stud.dat\n"
      "1 16 -30 0 10 1 0 0 0 1 0 0 0 1 stud.dat\n1 16 -10 0 10 1 0 0 0 1 0 0 0 1 stud.dat\n"
      "1 16 10 0 10 1 0 0 0 1 0 0 0 1 stud.dat\n1 16 30 0 10 1 0 0 0 1 0 0 0 1 stud.dat\n"
      "1 16 -20 20 0 1 0 0 0 1 0 0 0 1 stud4.dat\n1 16 0 20 0 1 0 0 0 1 0 0 0 1 stud4.dat\n"
      "1 16 20 20 0 1 0 0 0 1 0 0 0 1 stud4.dat\n0 NOFILE\n",
      "0 Wall on a baseplate\n1 2 0 0 0 1 0 0 0 1 0 0 0 1 3811.dat\n"
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n1 4 40 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 1 20 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n1 15 20 -56 0 1 0 0 0 1 0 0 0 1 3040b.dat\n"
      "1 0 -60 -24 0 0 0 1 0 1 0 -1 0 0 4070.dat\n1 14 -60 -32 -20 1 0 0 0 1 0 0 0 1 3024.dat\n"
      "1 71 0 -72 0 0.7071 0 0.7071 0 1 0 -0.7071 0 0.7071 3062b.dat\n",
  };
  count = sizeof seeds / sizeof seeds[0];
  return seeds;
}

}  // namespace lego::fuzz
