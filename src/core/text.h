#pragma once
// Text as LDraw and file systems compare it: ASCII case folded, bytes above 127 left as they are
// (a UTF-8 or Latin-1 name is never changed by it).
#include <cctype>
#include <string>
#include <string_view>

namespace lego {

inline std::string ascii_lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace lego
