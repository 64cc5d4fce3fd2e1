#pragma once
// Checks on the files both tools are asked to write, made before any work: a run that will fail
// to write its result must fail in the first second, not after the analysis, and no output may
// replace an input or another output of the same run.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace lego::app {

// The same file, existing or not: one inode, or one path once links and dots are resolved.
inline bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  if (std::filesystem::equivalent(a, b, ec)) return true;
  std::error_code ea, eb;
  // Absolute first: weakly_canonical leaves a relative path whose first part does not exist as
  // it is, so "out.mpd" and "./out.mpd" would differ.
  const auto ca =
      std::filesystem::weakly_canonical(std::filesystem::absolute(a, ea), ea).lexically_normal();
  const auto cb =
      std::filesystem::weakly_canonical(std::filesystem::absolute(b, eb), eb).lexically_normal();
  return !ea && !eb && ca == cb;
}

// Whether a new file can be made in `dir`, found by making one: permission bits say nothing
// about /proc, read-only mounts or a full quota, and root passes every access() check.
inline std::string why_not_writable(const std::filesystem::path& dir) {
  std::string probe = (dir / ".legolization-probe-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return {};
}

struct Output {
  std::string option;  // "-o", "--report"...
  std::string path;    // empty: not asked for
};

// Throws InputError when an output's folder is missing or not writable, when it is a folder or
// a read-only file, when it is one of the inputs, or when two options name the same file.
inline void check_outputs(const std::vector<Output>& outputs,
                          const std::vector<std::filesystem::path>& inputs) {
  namespace fs = std::filesystem;
  for (size_t i = 0; i < outputs.size(); ++i) {
    const Output& o = outputs[i];
    if (o.path.empty()) continue;
    const fs::path p(o.path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
      throw InputError(o.path, 0, o.option + ": the folder " + dir.string() + " does not exist");
    if (fs::is_directory(p, ec)) throw InputError(o.path, 0, o.option + ": is a folder");
    // A file its owner made read-only is one they meant to keep: never replaced (a rename over
    // it would succeed, and lose it and its mode, whatever its bits; root passes access()).
    if (const auto st = fs::status(p, ec);
        !ec && fs::is_regular_file(st) &&
        (st.permissions() & fs::perms::owner_write) == fs::perms::none)
      throw InputError(o.path, 0,
                       o.option +
                           ": the file is read-only; make it writable or remove it to "
                           "replace it");
    if (const std::string why = why_not_writable(dir); !why.empty())
      throw InputError(o.path, 0,
                       o.option + ": no file can be written in " + dir.string() + " (" + why + ")");
    for (const fs::path& input : inputs)
      if (same_file(p, input))
        throw InputError(o.path, 0, o.option + ": would overwrite the input " + input.string());
    for (size_t k = 0; k < i; ++k)
      if (!outputs[k].path.empty() && same_file(p, outputs[k].path))
        throw InputError(o.path, 0,
                         outputs[k].option + " and " + o.option +
                             " name the same file: one "
                             "would overwrite the other");
  }
}

}  // namespace lego::app
