#pragma once
// Files named as LDraw names them (any case) on a file system that tells case apart: each
// folder's listing is read once, and a name is matched by its lower case.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace lego::ldraw {

class CaseInsensitivePaths {
 public:
  // `relative` in lower case with forward slashes ("s/3001s01.dat"): the path on disk under
  // `dir` whatever the case of its folders and file, or nullopt when a part of it is missing.
  std::optional<std::filesystem::path> locate(const std::filesystem::path& dir,
                                              std::string_view relative);

 private:
  // Per folder: lower-case name -> name on disk.
  std::map<std::filesystem::path, std::unordered_map<std::string, std::string>> listings_;
  const std::unordered_map<std::string, std::string>& listing(const std::filesystem::path& dir);
};

}  // namespace lego::ldraw
