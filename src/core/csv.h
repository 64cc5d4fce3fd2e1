#pragma once
// The comma-separated files we read (the brick catalog, inventories, the BrickLink map): plain
// fields, no quoting.
#include <string>
#include <string_view>
#include <vector>

namespace lego {

// Without surrounding spaces, tabs and a carriage return.
inline std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return std::string(s);
}

// The fields of one line, trimmed; "a,,b," has four.
inline std::vector<std::string> split_csv(std::string_view line) {
  std::vector<std::string> fields;
  for (size_t start = 0;;) {
    const size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

}  // namespace lego
