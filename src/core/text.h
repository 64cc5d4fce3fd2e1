#pragma once
// Text as LDraw and file systems compare it: ASCII case folded, bytes above 127 left as they are
// (a UTF-8 or Latin-1 name is never changed by it); names made safe to print on one line.
#include <cctype>
#include <string>
#include <string_view>
#include <vector>

namespace lego {

inline std::string ascii_lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A name as one line of a report or an LDraw comment: control characters (a newline in a file
// name would start a line of its own, even a part line in a heat map) become '?'.
inline std::string one_line(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return out;
}

// How many parts a message names before it says "and N more".
inline constexpr size_t kPartsNamed = 3;

// "a; b; c and 4 more": the names shown (at most kPartsNamed) of `total` things.
inline std::string named_few(const std::vector<std::string>& shown, size_t total) {
  std::string out;
  for (size_t k = 0; k < shown.size(); ++k) out += (k ? "; " : "") + shown[k];
  if (total > shown.size()) out += " and " + std::to_string(total - shown.size()) + " more";
  return out;
}

// A part's title without the marks the LDraw library puts before it: '~' (a sub-part, or moved
// or obsolete), '_' (a physical colour), '=' (an alias), '|' (a sub-part's own), and spaces.
inline std::string_view without_title_marks(std::string_view title) {
  while (!title.empty() && (title.front() == '~' || title.front() == '_' || title.front() == '=' ||
                            title.front() == '|' || title.front() == ' '))
    title.remove_prefix(1);
  return title;
}

// A part's name as a builder reads it: without the library's marks, its runs of spaces one (the
// library aligns its titles: "Brick  1 x  2"), without " (Obsolete)".
inline std::string readable_part_name(std::string_view title) {
  std::string out;
  for (const char c : without_title_marks(title))
    if (c != ' ' || (!out.empty() && out.back() != ' ')) out += c;
  while (!out.empty() && out.back() == ' ') out.pop_back();
  if (out.ends_with(" (Obsolete)")) out.resize(out.size() - 11);
  return out;
}

}  // namespace lego
