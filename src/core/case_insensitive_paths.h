#pragma once
// Files named in any case (as LDraw files and meshes made on Windows name them) on a file system
// that tells case apart: each folder's listing is read once, and a name is matched by its lower
// case.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace lego {

class CaseInsensitivePaths {
 public:
  // `relative` in lower case with forward slashes ("s/3001s01.dat"): the path on disk under
  // `dir` whatever the case of its folders and file, or nullopt when a part of it is missing.
  std::optional<std::filesystem::path> locate(const std::filesystem::path& dir,
                                              std::string_view relative);
  // The file at `path` (absolute or relative to the working folder, any number of "..") in
  // whatever case it has on disk: the longest part of it that exists as written, then the rest
  // matched by lower case. nullopt when there is no such file.
  std::optional<std::filesystem::path> find(const std::filesystem::path& path);

 private:
  // Per folder: lower-case name -> name on disk.
  std::map<std::filesystem::path, std::unordered_map<std::string, std::string>> listings_;
  const std::unordered_map<std::string, std::string>& listing(const std::filesystem::path& dir);
};

}  // namespace lego
