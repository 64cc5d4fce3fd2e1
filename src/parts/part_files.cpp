#include "parts/part_files.h"

#include <fmt/format.h>

#include <cctype>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/brick_catalog.h"

namespace lego::parts {
namespace fs = std::filesystem;

std::string safe_reference(std::string_view reference) {
  std::string out = normalize_reference(reference);
  while (!out.empty() && std::isspace(static_cast<unsigned char>(out.back()))) out.pop_back();
  if (out.empty() || out.front() == '/' || (out.size() > 1 && out[1] == ':')) return {};
  size_t start = 0;
  while (start <= out.size()) {
    const size_t slash = out.find('/', start);
    const std::string_view part = std::string_view(out).substr(
        start, slash == std::string::npos ? std::string::npos : slash - start);
    if (part == "..") return {};
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return out;
}

std::optional<std::string> read_regular_file(const fs::path& path, std::string& why) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::is_regular_file(status)) {
    why = fs::exists(status) ? "not a regular file: " + path.string()
                             : "cannot open " + path.string();
    return std::nullopt;
  }
  const auto size = fs::file_size(path, ec);
  if (ec || size > kMaxFileBytes) {
    why = "larger than 64 MB: " + path.string();
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    why = "cannot open " + path.string();
    return std::nullopt;
  }
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

LibraryFiles::LibraryFiles(std::vector<fs::path> library_dirs) : dirs_(std::move(library_dirs)) {}

std::optional<PartFile> LibraryFiles::read(const fs::path& path, std::string& why) {
  const std::string key = "file:" + path.lexically_normal().string();
  auto it = texts_.find(key);
  if (it == texts_.end()) {
    auto text = read_regular_file(path, why);
    if (!text) return std::nullopt;
    it = texts_.emplace(key, std::make_unique<std::string>(std::move(*text))).first;
  }
  return PartFile{key, it->second.get()};
}

std::optional<PartFile> LibraryFiles::find(std::string_view reference, std::string& why) {
  const std::string name = safe_reference(reference);
  if (name.empty()) {
    why = fmt::format("refused: '{}' points outside the library", reference);
    return std::nullopt;
  }
  auto known = found_.find(name);
  if (known == found_.end()) {
    std::optional<std::string> key;
    for (const fs::path& dir : dirs_) {
      for (const char* folder : {"parts", "p", "unofficial/parts", "unofficial/p"})
        if (auto path = paths_.locate(dir / folder, name)) {
          std::string ignored;
          if (auto file = read(*path, ignored)) {
            key = file->key;
            break;
          }
        }
      if (key) break;
    }
    known = found_.emplace(name, key).first;
  }
  if (!known->second) {
    why = fmt::format("'{}' is not in the LDraw library", reference);
    return std::nullopt;
  }
  return PartFile{*known->second, texts_.at(*known->second).get()};
}

}  // namespace lego::parts
