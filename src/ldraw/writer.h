#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/assembly.h"
#include "ldraw/color_table.h"
#include "ldraw/transform.h"

namespace lego::ldraw {

struct WriteOptions {
  std::string title = "Untitled";
  std::string name;  // `0 Name:`; defaults to the output file name
  std::string author = "legolization";
  bool steps = true;  // `0 STEP` between bricks of different Brick::source.step
};

// The LDraw transform of a brick of an assembly (origin at the top centre of its body).
Transform brick_transform(const Brick& brick, const std::array<int, 3>& origin_ldu);

// One .ldr: header, then one type-1 line per brick in the order given.
std::string to_ldr(const Assembly& assembly, const WriteOptions& options);

// One .mpd: a main model placing one submodel per build step (bricks grouped by
// Brick::source.step), each followed by `0 STEP`, so viewers show a step per submodel.
std::string to_mpd(const Assembly& assembly, const WriteOptions& options);

// Writes text next to `path` first and renames it into place, so a failed write never leaves a
// partial file. Throws InputError when the path cannot be written.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);
// Several files, all or none: each is written next to its path first, and only when every one
// is written are they renamed into place.
void write_files_atomically(
    const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// to_ldr or to_mpd by the extension of `path`; the name defaults to its file name.
std::string model_text(const std::filesystem::path& path, const Assembly& assembly,
                       WriteOptions options);
// model_text, written atomically.
void write_model(const std::filesystem::path& path, const Assembly& assembly, WriteOptions options);

}  // namespace lego::ldraw
