#include "core/case_insensitive_paths.h"

#include <cctype>
#include "core/text.h"

namespace lego {

namespace fs = std::filesystem;

const std::unordered_map<std::string, std::string>& CaseInsensitivePaths::listing(
    const fs::path& dir) {
  auto [it, inserted] = listings_.try_emplace(dir);
  if (inserted) {
    std::error_code ec;
    for (fs::directory_iterator d(dir, ec), end; !ec && d != end; d.increment(ec)) {
      std::string name = d->path().filename().string();
      it->second.emplace(ascii_lower(name), std::move(name));
    }
  }
  return it->second;
}

std::optional<fs::path> CaseInsensitivePaths::locate(const fs::path& dir,
                                                     std::string_view relative) {
  fs::path current = dir;
  size_t start = 0;
  while (start <= relative.size()) {
    const size_t slash = relative.find('/', start);
    const std::string part(
        relative.substr(start, slash == std::string_view::npos ? relative.npos : slash - start));
    if (!part.empty()) {
      const auto& names = listing(current);
      auto it = names.find(part);
      if (it == names.end()) return std::nullopt;
      current /= it->second;
    }
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  return current;
}

std::optional<fs::path> CaseInsensitivePaths::find(const fs::path& path) {
  std::error_code ec;
  const fs::path full = fs::absolute(path, ec).lexically_normal();
  if (ec) return std::nullopt;
  if (fs::exists(full, ec)) return full;
  fs::path existing = full;
  std::string rest;
  while (existing.has_relative_path() && !fs::exists(existing, ec)) {
    const std::string name = ascii_lower(existing.filename().string());
    rest = rest.empty() ? name : name + "/" + rest;
    existing = existing.parent_path();
  }
  return locate(existing, rest);
}

}  // namespace lego
