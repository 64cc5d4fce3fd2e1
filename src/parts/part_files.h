#pragma once
// Finding the files a part is drawn with, as LDraw tools do: a model's embedded FILE blocks
// first, then the libraries' parts/ and p/ (with their s/ and 48/ subfolders, unofficial/ too),
// names matched case-insensitively with either slash. A reference resolves only inside those
// places: absolute paths, "..", devices and FIFOs are refused, and no file over kMaxFileBytes is
// read.
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/case_insensitive_paths.h"

namespace lego::parts {

inline constexpr size_t kMaxFileBytes = 64u << 20;

// A file found: its text, and a key naming it uniquely (for caches).
struct PartFile {
  std::string key;
  const std::string* text = nullptr;
};

// The libraries' files, read once per process.
class LibraryFiles {
 public:
  explicit LibraryFiles(std::vector<std::filesystem::path> library_dirs);

  // A file referenced inside a part ("s\3001s01.dat", "stud.dat", "48/1-4cyli.dat"), or
  // nullopt with `why`.
  std::optional<PartFile> find(std::string_view reference, std::string& why);
  // A part file at a path the model reader found (next to the model, or in a library).
  std::optional<PartFile> read(const std::filesystem::path& path, std::string& why);
  const std::vector<std::filesystem::path>& dirs() const { return dirs_; }

 private:
  std::vector<std::filesystem::path> dirs_;
  CaseInsensitivePaths paths_;
  std::unordered_map<std::string, std::unique_ptr<std::string>> texts_;  // by key
  std::unordered_map<std::string, std::optional<std::string>> found_;    // reference -> key
};

// A reference as LDraw names files: lower case, forward slashes ("S\\3001S01.DAT" ->
// "s/3001s01.dat"); empty when it tries to leave the library (absolute, "..").
std::string safe_reference(std::string_view reference);

// Reads a regular text file of at most kMaxFileBytes, or nullopt with `why`.
std::optional<std::string> read_regular_file(const std::filesystem::path& path, std::string& why);

}  // namespace lego::parts
